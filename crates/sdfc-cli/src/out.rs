//! Writing to stdout and stderr without a panic: `print!` and `eprintln!` panic when the
//! stream cannot be written (a reader that stopped reading, a full disk), which the CLI
//! contract forbids.

/// `eprintln!` that ignores a stderr that cannot be written: there is nowhere left to say
/// so, and the exit status still tells.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

/// `eprint!` in the same way as [`say!`].
macro_rules! say_part {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stderr(), $($arg)*);
    }};
}

use crate::Outcome;
use std::io::{ErrorKind, Write};
use std::sync::atomic::{AtomicBool, Ordering};

/// Whether the reader of stdout has gone: later output is dropped.
static CLOSED: AtomicBool = AtomicBool::new(false);

/// Writes `text` to stdout. A reader that closed the pipe (`sdfc eval ... | head -1`) asked
/// for no more, as ripgrep and the coreutils take it: the text and all later output are
/// dropped, and the command goes on to its files and its exit status (`check` still exits
/// 1 if a file failed, `render --compare -o` still writes the picture). `Err` only where the
/// write failed otherwise (a full disk): reported, with the environment's exit status.
pub fn print(text: &str) -> Result<(), Outcome> {
    if CLOSED.load(Ordering::Relaxed) {
        return Ok(());
    }
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == ErrorKind::BrokenPipe => {
            CLOSED.store(true, Ordering::Relaxed);
            Ok(())
        }
        Err(e) => {
            say!("sdfc: cannot write to stdout: {e}");
            Err(Outcome::EnvError)
        }
    }
}

/// [`print()`] as a command's last step: its outcome.
pub fn print_last(text: &str) -> Outcome {
    match print(text) {
        Ok(()) => Outcome::Ok,
        Err(o) => o,
    }
}

pub(crate) use {say, say_part};
