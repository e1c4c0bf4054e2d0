//! Byte-level mutation of a seed corpus: bit flips, byte insertion, deletion and duplication,
//! splicing two seeds, overwriting 32-bit words, replacing numbers in text with interesting
//! values (0, -1, 1e300, NaN, 2³², 10¹², huge and negative counts) and truncation. A few
//! mutations are stacked on each input.

use crate::rng::Rng;

/// The largest input a mutation produces (bytes).
pub const MAX_INPUT_LEN: usize = 256 * 1024;

/// Textual values that break parsers and unchecked arithmetic.
pub const INTERESTING_NUMBERS: &[&str] = &[
    "0",
    "-0",
    "-1",
    "1",
    "2",
    "1e300",
    "-1e300",
    "1e20",
    "-1e20",
    "1e-300",
    "NaN",
    "nan",
    "inf",
    "-inf",
    "4294967295",
    "4294967296",
    "2147483648",
    "-2147483649",
    "1000000000",
    "1000000000000",
    "-1000000000000",
    "18446744073709551615",
    "18446744073709551616",
    "9223372036854775807",
    "99999999999999999999999",
    "65536",
    "0.5",
    "3.4e38",
    "1.7976931348623157e308",
    "0x10",
    "",
];

/// 32-bit words that break binary length fields.
const INTERESTING_WORDS: &[u32] = &[
    0,
    1,
    2,
    0x7f,
    0x80,
    0xff,
    0xffff,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_ffff,
    0x0100_0000,
    1_000_000,
];

/// Where the numeric tokens of a text are: `(start, end)` byte ranges of runs like `-1.5e3`.
pub fn number_spans(bytes: &[u8]) -> Vec<(usize, usize)> {
    let limit = bytes.len().min(64 * 1024);
    let mut spans = Vec::new();
    let mut i = 0;
    while i < limit {
        let starts = bytes[i].is_ascii_digit()
            || (matches!(bytes[i], b'-' | b'+' | b'.')
                && bytes.get(i + 1).is_some_and(u8::is_ascii_digit));
        let glued = i > 0 && (bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_');
        if starts && !glued {
            let mut j = i + 1;
            while j < bytes.len()
                && (bytes[j].is_ascii_digit()
                    || matches!(bytes[j], b'.' | b'e' | b'E')
                    || (matches!(bytes[j], b'-' | b'+') && matches!(bytes[j - 1], b'e' | b'E')))
            {
                j += 1;
            }
            spans.push((i, j));
            i = j;
        } else {
            i += 1;
        }
    }
    spans
}

fn random_range(rng: &mut Rng, len: usize) -> (usize, usize) {
    let start = rng.below(len + 1);
    // Mostly short ranges, sometimes long ones.
    let max = if rng.chance(1, 4) {
        len - start
    } else {
        (len - start).min(16)
    };
    (start, start + rng.below(max + 1))
}

/// Applies one random mutation to `data`, drawing splice partners from `corpus`.
pub fn mutate_once(rng: &mut Rng, data: &mut Vec<u8>, corpus: &[Vec<u8>]) {
    let len = data.len();
    match rng.below(12) {
        0 if len > 0 => {
            let i = rng.below(len);
            data[i] ^= 1 << rng.below(8);
        }
        1 if len > 0 => {
            let i = rng.below(len);
            data[i] = *rng.pick(&[0u8, 0xff, 0x7f, 0x80, b'\n', b' ', b'"', b'<', b'-', b'9']);
        }
        2 => {
            let at = rng.below(len + 1);
            let n = 1 + rng.below(8);
            let bytes: Vec<u8> = (0..n).map(|_| rng.next_u64() as u8).collect();
            data.splice(at..at, bytes);
        }
        3 if len > 0 => {
            let (a, b) = random_range(rng, len);
            data.drain(a..b);
        }
        4 if len > 0 => {
            let (a, b) = random_range(rng, len);
            let copy = data[a..b].to_vec();
            let at = rng.below(data.len() + 1);
            let times = if rng.chance(1, 8) {
                1 + rng.below(64)
            } else {
                1
            };
            for _ in 0..times {
                data.splice(at..at, copy.iter().copied());
            }
        }
        5 if !corpus.is_empty() => {
            let other = rng.pick(corpus);
            let cut_a = rng.below(len + 1);
            let cut_b = rng.below(other.len() + 1);
            data.truncate(cut_a);
            data.extend_from_slice(&other[cut_b..]);
        }
        6 | 7 => {
            let spans = number_spans(data);
            if spans.is_empty() {
                let at = rng.below(len + 1);
                let value = rng.pick(INTERESTING_NUMBERS).as_bytes();
                data.splice(at..at, value.iter().copied());
            } else {
                let (a, b) = *rng.pick(&spans);
                let value = rng.pick(INTERESTING_NUMBERS).as_bytes();
                data.splice(a..b, value.iter().copied());
            }
        }
        8 if len >= 4 => {
            let i = rng.below(len - 3);
            let word = *rng.pick(INTERESTING_WORDS);
            let bytes = if rng.chance(1, 2) {
                word.to_le_bytes()
            } else {
                word.to_be_bytes()
            };
            data[i..i + 4].copy_from_slice(&bytes);
        }
        9 if len > 0 => {
            data.truncate(rng.below(len));
        }
        10 if len > 1 => {
            // Swap two ranges' first bytes (reorders tokens and lines).
            let i = rng.below(len);
            let j = rng.below(len);
            data.swap(i, j);
        }
        _ => {
            let at = rng.below(len + 1);
            let token: &[u8] = rng.pick::<&[u8]>(&[
                b"\n",
                b"\r\n",
                b"\0",
                b"-",
                b"[",
                b"]",
                b"{",
                b"}",
                b"<",
                b"/>",
                b"\"",
                b",",
                b":",
                b"\xff\xfe",
                b"\xc3",
                b"  ",
            ]);
            data.splice(at..at, token.iter().copied());
        }
    }
    data.truncate(MAX_INPUT_LEN);
}

/// A mutated copy of a random seed from `corpus` (1 to 8 stacked mutations).
pub fn mutate(rng: &mut Rng, corpus: &[Vec<u8>]) -> Vec<u8> {
    let mut data = if corpus.is_empty() {
        Vec::new()
    } else {
        rng.pick(corpus).clone()
    };
    let most = if rng.chance(1, 4) { 8 } else { 3 };
    let rounds = 1 + rng.below(most);
    for _ in 0..rounds {
        mutate_once(rng, &mut data, corpus);
    }
    data
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn number_spans_find_tokens_but_not_names() {
        let text = b"POINTS 12\nx1 -3.5e-2 ab7 .5";
        let spans: Vec<&[u8]> = number_spans(text)
            .iter()
            .map(|&(a, b)| &text[a..b])
            .collect();
        assert_eq!(spans, vec![&b"12"[..], b"-3.5e-2", b".5"]);
    }

    #[test]
    fn mutations_stay_bounded_and_change_inputs() {
        let corpus = vec![b"POINTS 3\nDATA ascii\n1 2 3\n".to_vec(), vec![0u8; 100]];
        let mut rng = Rng::new(9);
        let mut changed = 0;
        for _ in 0..2000 {
            let out = mutate(&mut rng, &corpus);
            assert!(out.len() <= MAX_INPUT_LEN);
            changed += usize::from(!corpus.contains(&out));
        }
        // A mutation can undo itself (e.g. a bit flipped twice), but rarely.
        assert!(changed > 1800, "{changed}");
    }
}
