//! A restricted reader of the pickles NumPy writes for object arrays (`np.savez` of a
//! dictionary, as Contact-GraspNet's `pred_grasps_cam = {segment_id: N×4×4 array}`).
//!
//! Nothing is executed: the reader interprets the pickle opcodes of protocols 2–5 that build
//! plain values (numbers, strings, bytes, tuples, lists, dictionaries) and exactly four
//! callables — `numpy.core.multiarray._reconstruct` (and its `numpy._core` spelling),
//! `numpy.dtype`, `numpy.core.multiarray.scalar` and `numpy.ndarray` as an argument — into
//! numeric arrays. Any other callable is refused by name. Every length is checked against the
//! bytes that remain before anything is allocated.

use super::array::{fortran_to_c, Array};
use std::rc::Rc;

/// A decoded pickle value.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Value {
    /// `None`.
    None,
    /// A boolean.
    Bool(bool),
    /// An integer.
    Int(i64),
    /// A float.
    Float(f64),
    /// A string.
    Str(String),
    /// Bytes.
    Bytes(Rc<[u8]>),
    /// A tuple or a list.
    Seq(Vec<Value>),
    /// A dictionary, in insertion order.
    Dict(Vec<(Value, Value)>),
    /// A NumPy array.
    Array(Array),
    /// An allowed global, `module.name`.
    Global(String),
    /// A NumPy dtype: its type string (`f4`, `<f8`, …) and byte order (`<`, `>`, `|`).
    Dtype(String, String),
    /// An array being rebuilt (after `_reconstruct`, before its state).
    ArrayStub,
}

const MAX_DEPTH: usize = 100_000;

/// Decodes a pickle; errors say which opcode or object is not accepted.
pub(crate) fn parse(bytes: &[u8]) -> Result<Value, String> {
    let mut stack: Vec<Value> = Vec::new();
    let mut marks: Vec<usize> = Vec::new();
    let mut memo: std::collections::HashMap<u32, Value> = std::collections::HashMap::new();
    let mut at = 0usize;
    let take = |at: &mut usize, n: usize| -> Result<&[u8], String> {
        if n > bytes.len() - *at {
            return Err(format!(
                "the pickle declares {n} bytes at offset {} but only {} remain",
                *at,
                bytes.len() - *at
            ));
        }
        let s = &bytes[*at..*at + n];
        *at += n;
        Ok(s)
    };
    let u32_at = |s: &[u8]| u32::from_le_bytes([s[0], s[1], s[2], s[3]]);
    loop {
        let op = *take(&mut at, 1)?.first().unwrap_or(&b'.');
        if stack.len() > MAX_DEPTH {
            return Err("the pickle is too deeply nested".into());
        }
        let pop = |stack: &mut Vec<Value>| {
            stack
                .pop()
                .ok_or_else(|| "the pickle pops an empty stack".to_string())
        };
        match op {
            0x80 => {
                take(&mut at, 1)?; // PROTO
            }
            0x95 => {
                take(&mut at, 8)?; // FRAME
            }
            b'.' => return pop(&mut stack),
            b'N' => stack.push(Value::None),
            0x88 => stack.push(Value::Bool(true)),
            0x89 => stack.push(Value::Bool(false)),
            b'J' => {
                let s = take(&mut at, 4)?;
                stack.push(Value::Int(i64::from(i32::from_le_bytes([
                    s[0], s[1], s[2], s[3],
                ]))));
            }
            b'K' => stack.push(Value::Int(i64::from(take(&mut at, 1)?[0]))),
            b'M' => {
                let s = take(&mut at, 2)?;
                stack.push(Value::Int(i64::from(u16::from_le_bytes([s[0], s[1]]))));
            }
            0x8a => {
                // LONG1: little-endian two's complement of n bytes.
                let n = take(&mut at, 1)?[0] as usize;
                let s = take(&mut at, n)?;
                if n > 8 {
                    return Err("an integer in the pickle is too large".into());
                }
                let mut buf = if s.last().is_some_and(|b| b & 0x80 != 0) {
                    [0xff; 8]
                } else {
                    [0; 8]
                };
                buf[..n].copy_from_slice(s);
                stack.push(Value::Int(i64::from_le_bytes(buf)));
            }
            b'G' => {
                let s = take(&mut at, 8)?;
                let mut b = [0u8; 8];
                b.copy_from_slice(s);
                stack.push(Value::Float(f64::from_be_bytes(b)));
            }
            b'X' | 0x8c | b'T' | b'U' | b'C' | b'B' | 0x8e | 0x8d => {
                let n = match op {
                    0x8c | b'U' | b'C' => take(&mut at, 1)?[0] as usize,
                    0x8e | 0x8d => {
                        let s = take(&mut at, 8)?;
                        let mut b = [0u8; 8];
                        b.copy_from_slice(s);
                        usize::try_from(u64::from_le_bytes(b)).unwrap_or(usize::MAX)
                    }
                    _ => u32_at(take(&mut at, 4)?) as usize,
                };
                let s = take(&mut at, n)?;
                stack.push(match op {
                    b'X' | 0x8c | 0x8d => Value::Str(
                        std::str::from_utf8(s)
                            .map_err(|_| "a string in the pickle is not UTF-8".to_string())?
                            .to_string(),
                    ),
                    // Protocol-2 byte strings (`T`, `U`) are latin-1 text in Python 3.
                    _ => Value::Bytes(Rc::from(s)),
                });
            }
            b'c' => {
                let mut line = || -> Result<String, String> {
                    let rest = &bytes[at..];
                    let end = rest
                        .iter()
                        .position(|&b| b == b'\n')
                        .ok_or("a GLOBAL opcode has no end of line")?;
                    at += end + 1;
                    Ok(String::from_utf8_lossy(&rest[..end]).into_owned())
                };
                let module = line()?;
                let name = line()?;
                stack.push(global(&module, &name)?);
            }
            0x93 => {
                let name = pop(&mut stack)?;
                let module = pop(&mut stack)?;
                match (module, name) {
                    (Value::Str(m), Value::Str(n)) => stack.push(global(&m, &n)?),
                    _ => return Err("STACK_GLOBAL needs two strings".into()),
                }
            }
            b'q' => {
                let key = u32::from(take(&mut at, 1)?[0]);
                memo.insert(key, stack.last().cloned().unwrap_or(Value::None));
            }
            b'r' => {
                let key = u32_at(take(&mut at, 4)?);
                memo.insert(key, stack.last().cloned().unwrap_or(Value::None));
            }
            0x94 => {
                let key = memo.len() as u32;
                memo.insert(key, stack.last().cloned().unwrap_or(Value::None));
            }
            b'h' | b'j' => {
                let key = if op == b'h' {
                    u32::from(take(&mut at, 1)?[0])
                } else {
                    u32_at(take(&mut at, 4)?)
                };
                stack.push(
                    memo.get(&key)
                        .cloned()
                        .ok_or_else(|| format!("the pickle refers to memo {key}, never stored"))?,
                );
            }
            b'(' => marks.push(stack.len()),
            b')' => stack.push(Value::Seq(Vec::new())),
            b']' => stack.push(Value::Seq(Vec::new())),
            b'}' => stack.push(Value::Dict(Vec::new())),
            0x85..=0x87 => {
                let n = (op - 0x84) as usize;
                if stack.len() < n {
                    return Err("the pickle pops an empty stack".into());
                }
                let items = stack.split_off(stack.len() - n);
                stack.push(Value::Seq(items));
            }
            b't' | b'l' | b'd' => {
                let mark = marks.pop().ok_or("the pickle has no MARK")?;
                let items = stack.split_off(mark.min(stack.len()));
                stack.push(if op == b'd' {
                    Value::Dict(pairs(items)?)
                } else {
                    Value::Seq(items)
                });
            }
            b'a' => {
                let item = pop(&mut stack)?;
                match stack.last_mut() {
                    Some(Value::Seq(list)) => list.push(item),
                    _ => return Err("APPEND to something that is not a list".into()),
                }
            }
            b'e' => {
                let mark = marks.pop().ok_or("the pickle has no MARK")?;
                let items = stack.split_off(mark.min(stack.len()));
                match stack.last_mut() {
                    Some(Value::Seq(list)) => list.extend(items),
                    _ => return Err("APPENDS to something that is not a list".into()),
                }
            }
            b's' => {
                let value = pop(&mut stack)?;
                let key = pop(&mut stack)?;
                match stack.last_mut() {
                    Some(Value::Dict(d)) => d.push((key, value)),
                    _ => return Err("SETITEM on something that is not a dictionary".into()),
                }
            }
            b'u' => {
                let mark = marks.pop().ok_or("the pickle has no MARK")?;
                let items = stack.split_off(mark.min(stack.len()));
                let new = pairs(items)?;
                match stack.last_mut() {
                    Some(Value::Dict(d)) => d.extend(new),
                    _ => return Err("SETITEMS on something that is not a dictionary".into()),
                }
            }
            b'R' => {
                let args = pop(&mut stack)?;
                let callable = pop(&mut stack)?;
                stack.push(reduce(callable, args)?);
            }
            b'b' => {
                let state = pop(&mut stack)?;
                let target = pop(&mut stack)?;
                stack.push(build(target, state)?);
            }
            other => {
                return Err(format!(
                    "pickle opcode 0x{other:02x} at offset {} is not read (only NumPy arrays \
                     in plain containers are)",
                    at - 1
                ))
            }
        }
    }
}

fn pairs(items: Vec<Value>) -> Result<Vec<(Value, Value)>, String> {
    if !items.len().is_multiple_of(2) {
        return Err("a dictionary in the pickle has a key without a value".into());
    }
    let mut out = Vec::with_capacity(items.len() / 2);
    let mut it = items.into_iter();
    while let (Some(k), Some(v)) = (it.next(), it.next()) {
        out.push((k, v));
    }
    Ok(out)
}

fn global(module: &str, name: &str) -> Result<Value, String> {
    let numpy_core = matches!(module, "numpy.core.multiarray" | "numpy._core.multiarray");
    match (module, name) {
        (_, "_reconstruct" | "scalar") if numpy_core => Ok(Value::Global(format!("numpy.{name}"))),
        ("numpy", "ndarray" | "dtype") => Ok(Value::Global(format!("numpy.{name}"))),
        _ => Err(format!(
            "the pickle calls {module}.{name}, which is not read (only NumPy arrays in plain \
             containers are)"
        )),
    }
}

fn reduce(callable: Value, args: Value) -> Result<Value, String> {
    let Value::Global(name) = callable else {
        return Err("the pickle calls something that is not a function".into());
    };
    let Value::Seq(args) = args else {
        return Err(format!("{name} is called without an argument tuple"));
    };
    match name.as_str() {
        "numpy._reconstruct" => Ok(Value::ArrayStub),
        "numpy.dtype" => match args.first() {
            Some(Value::Str(t)) => Ok(Value::Dtype(t.clone(), "|".into())),
            _ => Err("numpy.dtype needs a type string".into()),
        },
        "numpy.scalar" => match (args.first(), args.get(1)) {
            (Some(Value::Dtype(t, order)), Some(Value::Bytes(b))) => {
                let a = array_from_bytes(vec![], t, order, b, false)?;
                let v = a.data.first().copied().unwrap_or(f64::NAN);
                Ok(if t.contains('f') {
                    Value::Float(v)
                } else {
                    Value::Int(v as i64)
                })
            }
            _ => Err("numpy scalar needs a dtype and bytes".into()),
        },
        _ => Err(format!("{name} cannot be called")),
    }
}

fn build(target: Value, state: Value) -> Result<Value, String> {
    let Value::Seq(state) = state else {
        return Err("an object's state in the pickle is not a tuple".into());
    };
    match target {
        Value::Dtype(t, _) => {
            // (version, byte order, ...).
            let order = match state.get(1) {
                Some(Value::Str(o)) => o.clone(),
                _ => "|".into(),
            };
            Ok(Value::Dtype(t, order))
        }
        Value::ArrayStub => {
            // (version, shape, dtype, is_fortran, raw data).
            let shape = match state.get(1) {
                Some(Value::Seq(dims)) => dims
                    .iter()
                    .map(|d| match d {
                        Value::Int(n) if *n >= 0 => Ok(*n as usize),
                        _ => Err("an array's shape in the pickle is not whole numbers".to_string()),
                    })
                    .collect::<Result<Vec<_>, _>>()?,
                _ => return Err("an array in the pickle has no shape".into()),
            };
            if let (Some(Value::Dtype(t, _)), Some(Value::Seq(items))) =
                (state.get(2), state.get(4))
            {
                // An object array keeps its Python objects as a list.
                if t.trim_start_matches(['<', '>', '|', '=']).starts_with('O') {
                    return Ok(match (shape.as_slice(), items.as_slice()) {
                        ([], [one]) => one.clone(),
                        _ => Value::Seq(items.clone()),
                    });
                }
            }
            let (Some(Value::Dtype(t, order)), Some(Value::Bool(fortran)), Some(Value::Bytes(b))) =
                (state.get(2), state.get(3), state.get(4))
            else {
                return Err(
                    "an array in the pickle is not numbers (dtype, order and data expected)".into(),
                );
            };
            array_from_bytes(shape, t, order, b, *fortran).map(Value::Array)
        }
        _ => Err("the pickle sets the state of an object that is not a NumPy array".into()),
    }
}

/// An array from raw bytes of a dtype such as `f4` / `<f8` / `i8`, checked against the shape.
fn array_from_bytes(
    shape: Vec<usize>,
    type_str: &str,
    order: &str,
    bytes: &[u8],
    fortran: bool,
) -> Result<Array, String> {
    let t = type_str.trim_start_matches(['<', '>', '|', '=']);
    let big = order == ">" || type_str.starts_with('>');
    let (kind, size) = t.split_at(1);
    let size: usize = size
        .parse()
        .map_err(|_| format!("dtype '{type_str}' is not a number type this reads"))?;
    let count = shape
        .iter()
        .try_fold(1usize, |n, &d| n.checked_mul(d))
        .ok_or("an array's shape in the pickle is too large")?;
    if count.checked_mul(size) != Some(bytes.len()) {
        return Err(format!(
            "an array in the pickle declares {count} values of {size} bytes but holds {} bytes",
            bytes.len()
        ));
    }
    let values: Vec<f64> = bytes
        .chunks_exact(size)
        .map(|c| {
            let mut b = [0u8; 8];
            if big {
                b[..size].copy_from_slice(c);
                b[..size].reverse();
            } else {
                b[..size].copy_from_slice(c);
            }
            match (kind, size) {
                ("f", 8) => Ok(f64::from_le_bytes(b)),
                ("f", 4) => Ok(f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))),
                ("i", 1 | 2 | 4 | 8) => {
                    let shift = 64 - 8 * size as u32;
                    Ok(((i64::from_le_bytes(b) << shift) >> shift) as f64)
                }
                ("u", 1 | 2 | 4 | 8) | ("b", 1) => Ok(u64::from_le_bytes(b) as f64),
                _ => Err(format!(
                    "dtype '{type_str}' is not a number type this reads"
                )),
            }
        })
        .collect::<Result<_, _>>()?;
    let data = if fortran {
        fortran_to_c(&shape, &values)
    } else {
        values
    };
    Ok(Array { shape, data })
}
