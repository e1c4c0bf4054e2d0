//! Findings that are known and being fixed elsewhere. The CI slice tolerates (and prints) a
//! finding only if its target and a fragment of its message match an entry here; everything
//! else fails the test. Remove an entry when its fix is merged.

/// A known, not yet fixed finding.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct KnownFinding {
    /// The fuzz target that reaches it.
    pub target: &'static str,
    /// A fragment of the finding's message (signature or text) that identifies it.
    pub fragment: &'static str,
    /// Where it is tracked.
    pub issue: &'static str,
}

/// The known findings (see the module documentation). Every finding of the long runs recorded
/// in `TESTING.md` is fixed: its reproducer under `findings/` replays without a finding, so
/// the CI slice tolerates nothing.
pub const KNOWN_FINDINGS: &[KnownFinding] = &[];

/// The known finding that covers a failure of `target` with this signature and message.
pub fn known(target: &str, signature: &str, message: &str) -> Option<&'static KnownFinding> {
    KNOWN_FINDINGS.iter().find(|k| {
        k.target == target && (signature.contains(k.fragment) || message.contains(k.fragment))
    })
}
