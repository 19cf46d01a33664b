//! Reports on stdout (`lux ies info`; `lux info` does the same in its own file, which tests
//! include). A reader that stops early (`lux ies info … | head`) closes the pipe; that is not
//! an error: the command stops writing and exits 0 without a message (`println!` would panic
//! with "failed printing to stdout: Broken pipe" and exit 101). Other write errors (a full
//! disk behind a redirection) are errors: the command exits non-zero and says so.

use std::io::{ErrorKind, Write};

/// Writes `text` to stdout and flushes; a closed pipe ends the output quietly (`Ok`).
pub fn print(text: &str) -> Result<(), String> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(format!("cannot write to stdout: {e}")),
    }
}
