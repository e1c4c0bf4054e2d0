//! Reading JSON Lines input (a file or stdin) with errors that name the line.

use crate::bad_input;
use anyhow::{Context, Result};
use serde::de::DeserializeOwned;
use std::io::{BufRead, BufReader};
use std::path::Path;

/// Opens `path`, or stdin when `None` or `-`.
pub fn open_input(path: Option<&Path>) -> Result<Box<dyn BufRead>> {
    match path {
        Some(p) if p != Path::new("-") => {
            let file = graspath::input::open(p)
                .map_err(|e| bad_input!("{}: cannot open: {e}", p.display()))?;
            Ok(Box::new(BufReader::new(file)))
        }
        _ => Ok(Box::new(BufReader::new(std::io::stdin()))),
    }
}

/// Reads every non-blank line as a `T`, calling `each(line_number, value)` in order.
/// `source` names the input in errors (`<stdin>` or the path).
pub fn for_each_line<T: DeserializeOwned>(
    input: Box<dyn BufRead>,
    source: &str,
    mut each: impl FnMut(usize, T) -> Result<()>,
) -> Result<()> {
    for (index, line) in input.lines().enumerate() {
        let number = index + 1;
        let line = line.map_err(|e| bad_input!("{source}: line {number}: cannot read: {e}"))?;
        if line.trim().is_empty() {
            continue;
        }
        let value: T = serde_json::from_str(&line)
            .map_err(|e| bad_input!("{source}: line {number}: not a valid input object: {e}"))?;
        each(number, value).with_context(|| format!("{source}: line {number}"))?;
    }
    Ok(())
}

/// The name of an input for messages.
pub fn source_name(path: Option<&Path>) -> String {
    match path {
        Some(p) if p != Path::new("-") => p.display().to_string(),
        _ => "<stdin>".to_string(),
    }
}
