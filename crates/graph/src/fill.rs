//! The one pass that sets buffers to a word by transfers (counters to zero, list heads to
//! "empty"), so passes that start from known contents say what, not how.

use leakless_device::sync::Access;

use crate::graph::{BufferHandle, Graph};
use crate::name::PassName;

/// A range of a buffer set to one word.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fill {
    pub offset: u64,
    /// Bytes from `offset`; `None`: to the buffer's end.
    pub size: Option<u64>,
    pub word: u32,
}

impl Fill {
    /// The whole buffer.
    pub const fn whole(word: u32) -> Fill {
        Fill { offset: 0, size: None, word }
    }

    /// `size` bytes from `offset` (both multiples of 4).
    pub const fn range(offset: u64, size: u64, word: u32) -> Fill {
        Fill { offset, size: Some(size), word }
    }
}

impl Graph<'_> {
    /// Adds the pass `name` that sets each target's ranges to their words.
    pub fn fill(&mut self, name: PassName, targets: &mut [(&mut BufferHandle, &[Fill])]) {
        let mut pass = self.pass(name);
        let writes: Vec<_> = targets
            .iter_mut()
            .map(|(buffer, fills)| (pass.write(&mut **buffer, Access::TransferWrite), fills.to_vec()))
            .collect();
        pass.record(move |ctx| {
            for (target, fills) in &writes {
                let buffer = ctx.buffer(*target);
                for f in fills {
                    let size = f.size.unwrap_or(buffer.size() - f.offset);
                    ctx.cmd.fill_buffer(buffer, f.offset, size, f.word);
                }
            }
            Ok(())
        });
    }
}
