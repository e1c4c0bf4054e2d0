//! Reading JSON Lines input (a file or stdin) with errors that name the line.

use crate::bad_input;
use anyhow::{Context, Result};
use serde::de::DeserializeOwned;
use std::io::{BufRead, BufReader, Read};
use std::path::Path;

/// Opens `path`, or stdin when `None` or `-`.
pub(crate) fn open_input(path: Option<&Path>) -> Result<Box<dyn BufRead>> {
    match path {
        Some(p) if p != Path::new("-") => {
            let file = graspath::input::open(p)
                .map_err(|e| bad_input!("{}: cannot open: {e}", p.display()))?;
            Ok(Box::new(BufReader::new(file)))
        }
        _ => Ok(Box::new(BufReader::new(std::io::stdin()))),
    }
}

/// The longest input line read (bytes, 1 MiB): a line holds one configuration or pose, a few
/// hundred bytes; an input without line breaks (a binary file, `/dev/zero`) is refused at this
/// length instead of being held whole.
pub(crate) const MAX_LINE_BYTES: usize = 1 << 20;

/// Reads every non-blank line as a `T`, calling `each(line_number, value)` in order.
/// `source` names the input in errors (`<stdin>` or the path). A line longer than
/// [`MAX_LINE_BYTES`] is an error.
pub(crate) fn for_each_line<T: DeserializeOwned>(
    mut input: Box<dyn BufRead>,
    source: &str,
    mut each: impl FnMut(usize, T) -> Result<()>,
) -> Result<()> {
    let mut buffer = Vec::new();
    for number in 1.. {
        buffer.clear();
        let read = (&mut input)
            .take(MAX_LINE_BYTES as u64 + 1)
            .read_until(b'\n', &mut buffer)
            .map_err(|e| bad_input!("{source}: line {number}: cannot read: {e}"))?;
        if read == 0 {
            break;
        }
        if buffer.len() > MAX_LINE_BYTES {
            return Err(bad_input!(
                "{source}: line {number}: longer than {MAX_LINE_BYTES} bytes (is this JSON \
                 Lines, one object per line?)"
            ));
        }
        let Ok(line) = std::str::from_utf8(&buffer) else {
            return Err(bad_input!("{source}: line {number}: not UTF-8 text"));
        };
        if line.trim().is_empty() {
            continue;
        }
        let value: T = serde_json::from_str(line).map_err(|e| {
            let e = graspath::input::plain_serde_message(&e.to_string());
            bad_input!("{source}: line {number}: not a valid input object: {e}")
        })?;
        each(number, value).with_context(|| format!("{source}: line {number}"))?;
    }
    Ok(())
}

/// The name of an input for messages.
pub(crate) fn source_name(path: Option<&Path>) -> String {
    match path {
        Some(p) if p != Path::new("-") => p.display().to_string(),
        _ => "<stdin>".to_string(),
    }
}
