//! The harness the CLI's end-to-end tests share: temporary directories and running `sdfc`.
#![allow(dead_code)] // each test file uses its own part of it

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A fresh, empty directory under the system temp dir, removed when dropped.
pub struct TempDir(pub PathBuf);

impl TempDir {
    pub fn new(name: &str) -> TempDir {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let dir =
            std::env::temp_dir().join(format!("sdfc-cli-test-{}-{n}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
        TempDir(dir)
    }

    pub fn write(&self, name: &str, contents: impl AsRef<[u8]>) -> PathBuf {
        let path = self.0.join(name);
        std::fs::write(&path, contents).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        path
    }

    pub fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

pub struct Run {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
}

impl Run {
    pub fn describe(&self) -> String {
        format!(
            "exit {}\n--- stdout ---\n{}\n--- stderr ---\n{}",
            self.code, self.stdout, self.stderr
        )
    }

    pub fn expect_code(self, code: i32) -> Run {
        assert_eq!(
            self.code,
            code,
            "unexpected exit status:\n{}",
            self.describe()
        );
        self
    }
}

/// Runs `sdfc` in `dir` with `args` and extra environment variables; checks that nothing
/// looks like a panic or a backtrace and that the exit status is one of the contract's.
pub fn sdfc_env(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Run {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_sdfc"));
    cmd.args(args).current_dir(dir).env("NO_COLOR", "1");
    for (k, v) in env {
        cmd.env(k, v);
    }
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("cannot run sdfc: {e}"));
    let run = Run {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    };
    for bad in [
        "panicked",
        "RUST_BACKTRACE",
        "stack backtrace",
        "internal error",
    ] {
        assert!(
            !run.stdout.contains(bad) && !run.stderr.contains(bad),
            "`sdfc {}` printed `{bad}`:\n{}",
            args.join(" "),
            run.describe()
        );
    }
    assert!(
        matches!(run.code, 0..=2),
        "`sdfc {}` exited with {} (killed by a signal?):\n{}",
        args.join(" "),
        run.code,
        run.describe()
    );
    run
}

/// Runs `sdfc` in `dir` with `args`.
pub fn sdfc_in(dir: &Path, args: &[&str]) -> Run {
    sdfc_env(dir, args, &[])
}

/// A path as the `&str` a command line takes.
pub fn s(p: &Path) -> &str {
    p.to_str().expect("temp paths are UTF-8")
}

/// The numbers `sdfc eval` printed, one per line.
pub fn eval_lines(run: &Run) -> Vec<f64> {
    run.stdout
        .lines()
        .map(|l| {
            l.parse::<f64>()
                .unwrap_or_else(|e| panic!("`{l}` is not a number ({e}):\n{}", run.describe()))
        })
        .collect()
}
