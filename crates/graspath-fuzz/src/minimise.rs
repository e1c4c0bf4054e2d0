//! Delta debugging (Zeller's ddmin) over bytes: the smallest input, found within a time
//! budget, for which a test still reproduces the same failure.

use std::time::Instant;

/// Shrinks `input` while `reproduces` holds, removing chunks of halving size (ddmin's
/// complement step), then single bytes. Stops at `deadline` with the best input so far.
pub fn ddmin(
    input: &[u8],
    deadline: Instant,
    mut reproduces: impl FnMut(&[u8]) -> bool,
) -> Vec<u8> {
    let mut current = input.to_vec();
    let mut parts = 2usize;
    while current.len() >= 2 && Instant::now() < deadline {
        let chunk = current.len().div_ceil(parts);
        let mut reduced = false;
        let mut start = 0;
        while start < current.len() && Instant::now() < deadline {
            let end = (start + chunk).min(current.len());
            let mut candidate = Vec::with_capacity(current.len() - (end - start));
            candidate.extend_from_slice(&current[..start]);
            candidate.extend_from_slice(&current[end..]);
            if reproduces(&candidate) {
                current = candidate;
                reduced = true;
                // Retry the same position: the next chunk has moved into it.
            } else {
                start = end;
            }
        }
        if reduced {
            parts = parts.saturating_sub(1).max(2);
        } else if chunk == 1 {
            break;
        } else {
            parts = (parts * 2).min(current.len());
        }
    }
    current
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn far() -> Instant {
        Instant::now() + Duration::from_secs(30)
    }

    #[test]
    fn finds_the_minimal_subsequence() {
        // The failure needs the bytes 'a', 'b', 'z' in this order somewhere in the input:
        // the unique 1-minimal input is "abz".
        let holds = |s: &[u8]| {
            let mut want = b"abz".iter().peekable();
            for b in s {
                if want.peek() == Some(&b) {
                    want.next();
                }
            }
            want.peek().is_none()
        };
        let input = b"xxxxaqqqqqqqbyyyyyyyyyyyyyyyyyyyzzzzwww".to_vec();
        assert!(holds(&input));
        assert_eq!(ddmin(&input, far(), holds), b"abz");
    }

    #[test]
    fn keeps_inputs_that_cannot_shrink_and_respects_the_deadline() {
        assert_eq!(ddmin(b"q", far(), |_| true), b"q");
        let input = vec![7u8; 10_000];
        let out = ddmin(&input, Instant::now(), |_| true);
        assert_eq!(out.len(), input.len());
        // A predicate on length only: anything of at least 10 bytes fails; the result is
        // exactly 10 bytes long.
        assert_eq!(ddmin(&input, far(), |s| s.len() >= 10).len(), 10);
    }
}
