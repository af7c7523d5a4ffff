//! Reading a text file line by line into a buffer that grows fallibly: a line longer than the
//! memory left (a corrupt or hostile file without newlines) is an error, not an abort, which
//! `BufRead::read_until` would be.

use crate::alloc::{grow, AllocError};
use std::io::{BufRead, ErrorKind};

/// Why a line could not be read.
pub(super) enum LineError {
    /// The reader failed.
    Io(std::io::Error),
    /// The line did not fit in memory.
    Memory(AllocError),
}

/// Reads one line, up to and including its `\n` (or to the end of the input), appending it to
/// `buf`. Returns the bytes read: 0 at the end of the input.
pub(super) fn read_line(
    input: &mut impl BufRead,
    buf: &mut Vec<u8>,
    what: &'static str,
) -> Result<usize, LineError> {
    let mut read = 0;
    loop {
        let (done, used) = {
            let available = match input.fill_buf() {
                Ok(bytes) => bytes,
                Err(e) if e.kind() == ErrorKind::Interrupted => continue,
                Err(e) => return Err(LineError::Io(e)),
            };
            let (done, used) = match available.iter().position(|&b| b == b'\n') {
                Some(i) => (true, i + 1),
                None => (available.is_empty(), available.len()),
            };
            grow(buf, used, what).map_err(LineError::Memory)?;
            buf.extend_from_slice(&available[..used]);
            (done, used)
        };
        input.consume(used);
        read += used;
        if done {
            return Ok(read);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_are_read_as_read_until_reads_them() {
        let text = b"v 0 0 0\r\n\nlast line without newline";
        let mut small = std::io::BufReader::with_capacity(3, &text[..]);
        let mut reference = &text[..];
        loop {
            let (mut ours, mut theirs) = (Vec::new(), Vec::new());
            let n = read_line(&mut small, &mut ours, "line").ok().unwrap();
            let m = reference.read_until(b'\n', &mut theirs).unwrap();
            assert_eq!((n, &ours), (m, &theirs));
            if n == 0 {
                break;
            }
        }
    }
}
