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

/// Writes `text` to stdout. `Err` holds the outcome to stop with: success where the reader
/// closed the pipe (`sdfc eval ... | head -1` asked for no more, as ripgrep and the
/// coreutils take it), an environment error, reported, where the write failed otherwise.
pub fn print(text: &str) -> Result<(), Outcome> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == ErrorKind::BrokenPipe => Err(Outcome::Ok),
        Err(e) => {
            say!("sdfc: cannot write to stdout: {e}");
            Err(Outcome::EnvError)
        }
    }
}

pub(crate) use {say, say_part};
