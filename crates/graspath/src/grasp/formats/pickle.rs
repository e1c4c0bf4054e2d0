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

/// The deepest nesting of containers (lists, tuples, dictionaries) a pickle may build. NumPy's
/// object arrays of dictionaries of arrays nest 3 deep; a limit keeps every walk over a decoded
/// value (cloning, comparing, dropping) far from the end of the stack.
pub(crate) const MAX_NESTING: u32 = 64;

/// The fewest bytes every pickle may decode to (the budget grows with its length).
const MIN_DECODED_BYTES: u64 = 64 << 20;

/// The most bytes one pickle may decode to, whatever its length.
pub(crate) const MAX_DECODED_BYTES: u64 = 2 << 30;

/// What a pickle may decode to: `MIN_DECODED_BYTES` plus 16 bytes per byte of pickle (a
/// 2-byte opcode makes a value of about 40 bytes), at most `MAX_DECODED_BYTES`. The memo
/// copies values: without a budget, a few hundred bytes that put a list twice into the next
/// one, again and again, decode to tens of gigabytes.
fn decoded_budget(len: usize) -> u64 {
    MIN_DECODED_BYTES
        .saturating_add((len as u64).saturating_mul(16))
        .min(MAX_DECODED_BYTES)
}

/// A value on the pickle machine's stack or in its memo, with what it costs: `weight`, the
/// bytes it takes (nodes and their contents), and `depth`, how deep its containers nest.
#[derive(Debug, Clone)]
struct Item {
    value: Value,
    weight: u64,
    depth: u32,
}

const NODE_BYTES: u64 = size_of::<Value>() as u64;

impl Item {
    /// A value that holds no other value (a number, a string, an array).
    fn leaf(value: Value) -> Self {
        let heap = match &value {
            Value::Str(s) | Value::Global(s) => s.len() as u64,
            Value::Bytes(b) => b.len() as u64,
            Value::Array(a) => 8 * (a.data.len() + a.shape.len()) as u64,
            Value::Dtype(t, o) => (t.len() + o.len()) as u64,
            _ => 0,
        };
        Self {
            value,
            weight: NODE_BYTES + heap,
            depth: 0,
        }
    }

    /// A list or tuple of `items`.
    fn seq(items: Vec<Item>) -> Self {
        let weight = NODE_BYTES + items.iter().map(|i| i.weight).sum::<u64>();
        let depth = 1 + items.iter().map(|i| i.depth).max().unwrap_or(0);
        Self {
            value: Value::Seq(items.into_iter().map(|i| i.value).collect()),
            weight,
            depth,
        }
    }
}

/// The decoding state: the bytes decoded so far against the budget.
struct Budget {
    spent: u64,
    limit: u64,
}

impl Budget {
    /// Counts `bytes` more of decoded values; an error past the budget.
    fn charge(&mut self, bytes: u64) -> Result<(), String> {
        self.spent = self.spent.saturating_add(bytes);
        if self.spent > self.limit {
            return Err(format!(
                "the pickle decodes to more than {} bytes (its memo repeats values): refused \
                 before it is built",
                self.limit
            ));
        }
        Ok(())
    }
}

/// Refuses an item nested deeper than [`MAX_NESTING`].
fn check_depth(item: &Item) -> Result<(), String> {
    if item.depth > MAX_NESTING {
        return Err(format!(
            "the pickle nests containers more than {MAX_NESTING} deep"
        ));
    }
    Ok(())
}

/// Decodes a pickle; errors say which opcode or object is not accepted. Memory is bounded
/// before it is used: every length is checked against the bytes that remain, the values built
/// (memo copies included) against a budget that grows with the pickle's length, and nesting
/// against [`MAX_NESTING`].
pub(crate) fn parse(bytes: &[u8]) -> Result<Value, String> {
    let mut stack: Vec<Item> = Vec::new();
    let mut marks: Vec<usize> = Vec::new();
    let mut memo: std::collections::HashMap<u32, Item> = std::collections::HashMap::new();
    let mut budget = Budget {
        spent: 0,
        limit: decoded_budget(bytes.len()),
    };
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
    let pop = |stack: &mut Vec<Item>| {
        stack
            .pop()
            .ok_or_else(|| "the pickle pops an empty stack".to_string())
    };
    loop {
        let op = *take(&mut at, 1)?.first().unwrap_or(&b'.');
        // Values that hold no other value, pushed as they are.
        let mut push_leaf = |stack: &mut Vec<Item>, value: Value| -> Result<(), String> {
            let item = Item::leaf(value);
            budget.charge(item.weight)?;
            stack.push(item);
            Ok(())
        };
        match op {
            0x80 => {
                take(&mut at, 1)?; // PROTO
            }
            0x95 => {
                take(&mut at, 8)?; // FRAME
            }
            b'.' => return pop(&mut stack).map(|i| i.value),
            b'N' => push_leaf(&mut stack, Value::None)?,
            0x88 => push_leaf(&mut stack, Value::Bool(true))?,
            0x89 => push_leaf(&mut stack, Value::Bool(false))?,
            b'J' => {
                let s = take(&mut at, 4)?;
                let v = i64::from(i32::from_le_bytes([s[0], s[1], s[2], s[3]]));
                push_leaf(&mut stack, Value::Int(v))?;
            }
            b'K' => {
                let v = i64::from(take(&mut at, 1)?[0]);
                push_leaf(&mut stack, Value::Int(v))?;
            }
            b'M' => {
                let s = take(&mut at, 2)?;
                push_leaf(
                    &mut stack,
                    Value::Int(i64::from(u16::from_le_bytes([s[0], s[1]]))),
                )?;
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
                push_leaf(&mut stack, Value::Int(i64::from_le_bytes(buf)))?;
            }
            b'G' => {
                let s = take(&mut at, 8)?;
                let mut b = [0u8; 8];
                b.copy_from_slice(s);
                push_leaf(&mut stack, Value::Float(f64::from_be_bytes(b)))?;
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
                let value = match op {
                    b'X' | 0x8c | 0x8d => Value::Str(
                        std::str::from_utf8(s)
                            .map_err(|_| "a string in the pickle is not UTF-8".to_string())?
                            .to_string(),
                    ),
                    // Protocol-2 byte strings (`T`, `U`) are latin-1 text in Python 3.
                    _ => Value::Bytes(Rc::from(s)),
                };
                push_leaf(&mut stack, value)?;
            }
            b'c' => {
                let mut line = || -> Result<String, String> {
                    let rest = &bytes[at..];
                    let end = rest
                        .iter()
                        .take(256)
                        .position(|&b| b == b'\n')
                        .ok_or("a GLOBAL opcode has no end of line within 256 bytes")?;
                    at += end + 1;
                    Ok(String::from_utf8_lossy(&rest[..end]).into_owned())
                };
                let module = line()?;
                let name = line()?;
                push_leaf(&mut stack, global(&module, &name)?)?;
            }
            0x93 => {
                let name = pop(&mut stack)?;
                let module = pop(&mut stack)?;
                match (module.value, name.value) {
                    (Value::Str(m), Value::Str(n)) => push_leaf(&mut stack, global(&m, &n)?)?,
                    _ => return Err("STACK_GLOBAL needs two strings".into()),
                }
            }
            b'q' | b'r' | 0x94 => {
                let key = match op {
                    b'q' => u32::from(take(&mut at, 1)?[0]),
                    b'r' => u32_at(take(&mut at, 4)?),
                    _ => memo.len() as u32,
                };
                let item = stack
                    .last()
                    .cloned()
                    .unwrap_or_else(|| Item::leaf(Value::None));
                budget.charge(item.weight)?;
                memo.insert(key, item);
            }
            b'h' | b'j' => {
                let key = if op == b'h' {
                    u32::from(take(&mut at, 1)?[0])
                } else {
                    u32_at(take(&mut at, 4)?)
                };
                let item = memo
                    .get(&key)
                    .ok_or_else(|| format!("the pickle refers to memo {key}, never stored"))?;
                // Charged before the copy is made.
                budget.charge(item.weight)?;
                stack.push(item.clone());
            }
            b'(' => marks.push(stack.len()),
            b')' | b']' => stack.push(Item::seq(Vec::new())),
            b'}' => stack.push(Item {
                value: Value::Dict(Vec::new()),
                weight: NODE_BYTES,
                depth: 1,
            }),
            0x85..=0x87 => {
                let n = (op - 0x84) as usize;
                if stack.len() < n {
                    return Err("the pickle pops an empty stack".into());
                }
                let items = stack.split_off(stack.len() - n);
                let item = Item::seq(items);
                check_depth(&item)?;
                stack.push(item);
            }
            b't' | b'l' | b'd' => {
                let mark = marks.pop().ok_or("the pickle has no MARK")?;
                let items = stack.split_off(mark.min(stack.len()));
                let item = if op == b'd' {
                    dict(items)?
                } else {
                    Item::seq(items)
                };
                check_depth(&item)?;
                stack.push(item);
            }
            b'a' | b'e' => {
                let items = if op == b'a' {
                    vec![pop(&mut stack)?]
                } else {
                    let mark = marks.pop().ok_or("the pickle has no MARK")?;
                    stack.split_off(mark.min(stack.len()))
                };
                let Some(Item {
                    value: Value::Seq(list),
                    weight,
                    depth,
                }) = stack.last_mut()
                else {
                    return Err("APPEND to something that is not a list".into());
                };
                for item in items {
                    *weight += item.weight;
                    *depth = (*depth).max(item.depth + 1);
                    list.push(item.value);
                }
                if *depth > MAX_NESTING {
                    return Err(format!(
                        "the pickle nests containers more than {MAX_NESTING} deep"
                    ));
                }
            }
            b's' | b'u' => {
                let items = if op == b's' {
                    let value = pop(&mut stack)?;
                    let key = pop(&mut stack)?;
                    vec![key, value]
                } else {
                    let mark = marks.pop().ok_or("the pickle has no MARK")?;
                    stack.split_off(mark.min(stack.len()))
                };
                let new = dict(items)?;
                let Some(Item {
                    value: Value::Dict(d),
                    weight,
                    depth,
                }) = stack.last_mut()
                else {
                    return Err("SETITEM on something that is not a dictionary".into());
                };
                let Value::Dict(pairs) = new.value else {
                    unreachable!("dict() builds a dictionary")
                };
                d.extend(pairs);
                *weight += new.weight - NODE_BYTES;
                *depth = (*depth).max(new.depth);
                if *depth > MAX_NESTING {
                    return Err(format!(
                        "the pickle nests containers more than {MAX_NESTING} deep"
                    ));
                }
            }
            b'R' => {
                let args = pop(&mut stack)?;
                let callable = pop(&mut stack)?;
                push_leaf(&mut stack, reduce(callable.value, args.value)?)?;
            }
            b'b' => {
                let state = pop(&mut stack)?;
                let target = pop(&mut stack)?;
                let built = build(target.value, state.value)?;
                // An object array's items are containers: its weight and depth are the
                // state's.
                let item = match built {
                    Value::Seq(_) | Value::Dict(_) => Item {
                        value: built,
                        weight: state.weight,
                        depth: state.depth,
                    },
                    other => Item::leaf(other),
                };
                budget.charge(item.weight)?;
                check_depth(&item)?;
                stack.push(item);
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

/// A dictionary of alternating keys and values.
fn dict(items: Vec<Item>) -> Result<Item, String> {
    let weight = NODE_BYTES + items.iter().map(|i| i.weight).sum::<u64>();
    let depth = 1 + items.iter().map(|i| i.depth).max().unwrap_or(0);
    let values = items.into_iter().map(|i| i.value).collect();
    Ok(Item {
        value: Value::Dict(pairs(values)?),
        weight,
        depth,
    })
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

/// The kind (`f`, `i`, `u`, `b`) and size in bytes of a NumPy type string such as `<f8`, `f4`,
/// `|u1`; any other type (complex, long double, half, strings, an empty or malformed name) is
/// refused with what it is, before any byte is read as it.
pub(crate) fn number_type(type_str: &str) -> Result<(char, usize), String> {
    let t = type_str.trim_start_matches(['<', '>', '|', '=']);
    let mut chars = t.chars();
    let kind = chars.next();
    let size = chars.as_str().parse::<usize>().ok();
    let shown = super::excerpt(type_str.as_bytes(), 16);
    match (kind, size) {
        (Some('f'), Some(4 | 8))
        | (Some('i' | 'u'), Some(1 | 2 | 4 | 8))
        | (Some('b'), Some(1)) => Ok((kind.unwrap_or('f'), size.unwrap_or(8))),
        (Some('c'), _) => Err(format!(
            "dtype '{shown}' holds complex numbers, which are refused (their imaginary part \
             would be lost); save the real part (np.real) if that is what is meant"
        )),
        (Some('f' | 'g'), Some(10 | 12 | 16)) | (Some('g'), _) => Err(format!(
            "dtype '{shown}' holds long doubles, which are not read; save the array as float64"
        )),
        (Some('f'), Some(2)) => Err(format!(
            "dtype '{shown}' holds half floats, which are not read; save the array as float32 \
             or float64"
        )),
        _ => Err(format!(
            "dtype '{shown}' is not a number type this reads (float32/64, integers, booleans)"
        )),
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
    let (kind, size) = number_type(type_str)?;
    let big = order == ">" || type_str.starts_with('>');
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
            match kind {
                'f' if size == 8 => f64::from_le_bytes(b),
                'f' => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
                'i' => {
                    let shift = 64 - 8 * size as u32;
                    ((i64::from_le_bytes(b) << shift) >> shift) as f64
                }
                _ => u64::from_le_bytes(b) as f64,
            }
        })
        .collect();
    let data = if fortran {
        fortran_to_c(&shape, &values)
    } else {
        values
    };
    Ok(Array { shape, data })
}
