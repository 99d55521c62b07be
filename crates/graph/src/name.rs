//! Pass names as constants: one value names a pass for the graph (its debug label, timing key
//! and crash marker), and says which group of the frame its time counts under, so the
//! benchmarks and the app's panel sum the same passes without matching strings.

/// A pass's name and the group of the frame it belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PassName {
    /// The label of the pass ("splat", "gather clear").
    pub label: &'static str,
    /// The part of the frame its time counts under ("splat", "hierarchy").
    pub group: &'static str,
}

impl PassName {
    pub const fn new(label: &'static str, group: &'static str) -> PassName {
        PassName { label, group }
    }
}

impl std::fmt::Display for PassName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.label)
    }
}
