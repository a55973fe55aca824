//! The output streams: a reader that stops reading, or a stream that cannot be written, is
//! never a panic (the CLI contract). Found by the CLI audit of 2026-12-04: `sdfc eval ... |
//! head -1` and any output to a full disk printed "internal error ... panicked", and a
//! diagnostic to an unwritable stderr aborted the process (status 134).

mod common;

use common::{s, TempDir};
use std::fs::{File, OpenOptions};
use std::io::Read;
use std::process::{Command, Stdio};

fn sdfc() -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_sdfc"));
    cmd.env("NO_COLOR", "1");
    cmd
}

fn dev_full() -> File {
    OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .expect("/dev/full (Linux)")
}

/// Enough points that the output is far larger than a pipe's buffer.
fn many_points(t: &TempDir) -> std::path::PathBuf {
    t.write("pts.csv", "0.5,0.25,0\n".repeat(200_000))
}

#[test]
fn a_reader_that_stops_reading_ends_the_output_quietly() {
    let t = TempDir::new("broken-pipe");
    let scene = t.write("sphere.sdf", "scene = sphere(1);\n");
    let pts = many_points(&t);
    let mut child = sdfc()
        .args(["eval", s(&scene), "--points", s(&pts)])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("sdfc runs");
    // Read one line's worth, then close the pipe, as `head -1` does.
    let mut out = child.stdout.take().expect("stdout");
    let mut first = [0u8; 8];
    out.read_exact(&mut first).expect("some output");
    drop(out);
    let mut stderr = String::new();
    child
        .stderr
        .take()
        .expect("stderr")
        .read_to_string(&mut stderr)
        .expect("stderr is UTF-8");
    let status = child.wait().expect("sdfc ends");
    assert_eq!(status.code(), Some(0), "stderr: {stderr}");
    assert!(stderr.is_empty(), "nothing to say: {stderr}");
}

#[test]
fn a_full_stdout_is_an_environment_error() {
    let t = TempDir::new("full-stdout");
    let scene = t.write("sphere.sdf", "scene = sphere(1);\n");
    let pts = many_points(&t);
    let wgsl = t.write("ok.wgsl", "fn f() -> f32 { return 1.0; }\n");
    for args in [
        vec!["compile", s(&scene)],
        vec!["compile", s(&scene), "--emit", "ast"],
        vec!["eval", s(&scene), "--points", s(&pts)],
        vec!["check", s(&scene), s(&wgsl)],
    ] {
        let out = sdfc()
            .args(&args)
            .stdout(dev_full())
            .output()
            .expect("sdfc runs");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(
            stderr.contains("cannot write to stdout") && !stderr.contains("internal error"),
            "{args:?}: {stderr}"
        );
    }
}

#[test]
fn an_unwritable_stderr_leaves_the_exit_status() {
    let t = TempDir::new("full-stderr");
    let broken = t.write("broken.sdf", "scene = spher(1);\n");
    let good = t.write("sphere.sdf", "scene = sphere(1);\n");
    for (args, code) in [
        (vec!["compile", s(&broken)], 1),
        (
            vec![
                "compile",
                s(&good),
                "--explain",
                "-o",
                s(&t.path("out.wgsl")),
            ],
            0,
        ),
        (vec!["compile", s(&t.path("missing.sdf"))], 2),
    ] {
        let out = sdfc()
            .args(&args)
            .stdout(Stdio::null())
            .stderr(dev_full())
            .output()
            .expect("sdfc runs");
        assert_eq!(out.status.code(), Some(code), "{args:?}");
    }
}

/// A closed stdout drops the lines, not the work: `check` still checks every file and exits
/// 1 if one failed (it had exited 0 at the first line it could not write).
#[test]
fn a_closed_stdout_keeps_the_exit_status() {
    let t = TempDir::new("closed-check");
    let bad = t.write("bad.sdf", "scene = spher(1);\n");
    let good = t.write("good.sdf", "scene = sphere(1);\n");
    for _ in 0..3 {
        let mut child = sdfc()
            .args(["check", s(&bad), s(&good)])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("sdfc runs");
        drop(child.stdout.take());
        let status = child.wait().expect("sdfc ends");
        assert_eq!(status.code(), Some(1));
    }
}
