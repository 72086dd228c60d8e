//! Writing to standard output without panicking when the reader goes away (`kairos … | head`).

use std::io::{ErrorKind, Write};

use super::Failure;

/// Writes `text` to standard output. A closed pipe ends the output quietly (`Ok(false)`: stop
/// writing); any other error is a run failure.
pub fn emit(text: &str) -> Result<bool, Failure> {
    let mut stdout = std::io::stdout().lock();
    match stdout
        .write_all(text.as_bytes())
        .and_then(|()| stdout.flush())
    {
        Ok(()) => Ok(true),
        Err(e) if e.kind() == ErrorKind::BrokenPipe => Ok(false),
        Err(e) => Err(Failure::io(format!("error: cannot write the output: {e}"))),
    }
}
