// Checks WGSL files with Tint, the WGSL compiler of Chrome, through Dawn's Node.js binding.
//
// Usage: node check_wgsl.mjs [--gles] FILE.wgsl... (or folders of them). Dawn's null backend
// runs Tint's front end (parser, resolver, uniformity analysis) and WebGPU's validation at
// the default limits, which is what a browser applies, without a GPU. With `--gles` Dawn
// runs on Mesa's software OpenGL ES (llvmpipe, through EGL without a display) at WebGPU's
// compatibility feature level, as Chrome does where there is no Vulkan: pipelines then also
// go through Tint's back-end transforms, its GLSL writer and Mesa's GLSL compiler. Each file
// becomes one shader module; a file with an `@compute` entry point also becomes a compute
// pipeline (layout "auto"), which checks the entry point against the limits. Prints one JSON
// line per file, {"file", "ok", "messages"}, and exits 1 if any file failed, 2 if Dawn gave
// no device.
import { create, globals } from 'webgpu';
import fs from 'node:fs';
import path from 'node:path';

Object.assign(globalThis, globals);

function files(args) {
  const out = [];
  for (const a of args) {
    if (fs.statSync(a).isDirectory()) {
      for (const f of fs.readdirSync(a).sort()) {
        if (f.endsWith('.wgsl')) out.push(path.join(a, f));
      }
    } else {
      out.push(a);
    }
  }
  return out;
}

// Tint's messages carry line and column; errors raised by WebGPU validation only text.
function text(m) {
  return `${m.type} ${m.lineNum}:${m.linePos}: ${m.message}`;
}

const args = process.argv.slice(2);
const gles = args[0] === '--gles';
if (gles) {
  args.shift();
  // Mesa's EGL otherwise looks for an X or Wayland display.
  process.env.EGL_PLATFORM ??= 'surfaceless';
}
const gpu = create([gles ? 'backend=opengles' : 'backend=null']);
const adapter = await gpu.requestAdapter(gles ? { featureLevel: 'compatibility' } : {});
const device = adapter && (await adapter.requestDevice());
if (!device) {
  console.error(`check_wgsl: Dawn offered no device on its ${gles ? 'OpenGL ES' : 'null'} backend`);
  process.exit(2);
}

let failed = 0;
for (const file of files(args)) {
  const code = fs.readFileSync(file, 'utf8');
  const messages = [];
  device.pushErrorScope('validation');
  const module = device.createShaderModule({ code });
  const info = await module.getCompilationInfo();
  for (const m of info.messages) messages.push(text(m));
  const moduleError = await device.popErrorScope();
  let ok = !moduleError && !info.messages.some((m) => m.type === 'error');
  if (moduleError && messages.length === 0) messages.push(`error: ${moduleError.message}`);
  // Every compute entry point gets a pipeline (a union read as data has two: `main` and the
  // blocks' pass `blocks_main`), each named, as a module of several needs.
  const entries = ok ? [...code.matchAll(/@compute[^{]*?fn\s+(\w+)\s*\(/g)].map((m) => m[1]) : [];
  for (const entryPoint of entries) {
    device.pushErrorScope('validation');
    try {
      await device.createComputePipelineAsync({ layout: 'auto', compute: { module, entryPoint } });
    } catch (e) {
      ok = false;
      messages.push(`error: pipeline ${entryPoint}: ${e.message}`);
    }
    const pipelineError = await device.popErrorScope();
    if (pipelineError) {
      ok = false;
      messages.push(`error: pipeline ${entryPoint}: ${pipelineError.message}`);
    }
  }
  if (!ok) failed++;
  console.log(JSON.stringify({ file, ok, messages }));
}
process.exit(failed ? 1 : 0);
