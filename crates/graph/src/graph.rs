//! Building a frame: resources are imported, passes declare their uses and record commands.

use leakless_device::sync::Access;
use leakless_device::{Buffer, Cmd, Image, Result};

/// A buffer known to the graph. Not `Clone`: writing it takes `&mut`.
#[derive(Debug)]
pub struct BufferHandle {
    id: usize,
}

/// An image known to the graph. Not `Clone`: writing it takes `&mut`.
#[derive(Debug)]
pub struct ImageHandle {
    id: usize,
}

#[doc(hidden)]
pub enum Resource<'r> {
    Buffer(&'r Buffer),
    Image(&'r Image),
}

type Record<'r> = Box<dyn FnOnce(&mut Cmd<'_>) -> Result<()> + 'r>;

pub(crate) struct Pass<'r> {
    pub name: String,
    pub uses: Vec<(usize, Access)>,
    pub record: Record<'r>,
}

/// One frame's passes, in execution order.
#[derive(Default)]
pub struct Graph<'r> {
    pub(crate) resources: Vec<Resource<'r>>,
    pub(crate) passes: Vec<Pass<'r>>,
}

impl<'r> Graph<'r> {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn import_buffer(&mut self, buffer: &'r Buffer) -> BufferHandle {
        self.resources.push(Resource::Buffer(buffer));
        BufferHandle { id: self.resources.len() - 1 }
    }

    pub fn import_image(&mut self, image: &'r Image) -> ImageHandle {
        self.resources.push(Resource::Image(image));
        ImageHandle { id: self.resources.len() - 1 }
    }

    /// Starts a pass; `name` is its debug label, timing key and crash marker.
    pub fn pass<'g>(&'g mut self, name: &str) -> PassBuilder<'g, 'r> {
        PassBuilder { graph: self, name: name.to_string(), uses: Vec::new() }
    }

    pub fn pass_names(&self) -> impl Iterator<Item = &str> {
        self.passes.iter().map(|p| p.name.as_str())
    }
}

/// Declares what one pass reads and writes; each declaration hands back the resource for the
/// recording closure to use.
pub struct PassBuilder<'g, 'r> {
    graph: &'g mut Graph<'r>,
    name: String,
    uses: Vec<(usize, Access)>,
}

/// Handles the graph can resolve to a resource.
pub trait Handle {
    type Target: ?Sized;
    #[doc(hidden)]
    fn id(&self) -> usize;
    #[doc(hidden)]
    fn resolve<'r>(resource: &Resource<'r>) -> &'r Self::Target;
}

impl Handle for BufferHandle {
    type Target = Buffer;
    fn id(&self) -> usize {
        self.id
    }
    fn resolve<'r>(resource: &Resource<'r>) -> &'r Buffer {
        match resource {
            Resource::Buffer(b) => b,
            Resource::Image(_) => unreachable!("buffer handle names an image"),
        }
    }
}

impl Handle for ImageHandle {
    type Target = Image;
    fn id(&self) -> usize {
        self.id
    }
    fn resolve<'r>(resource: &Resource<'r>) -> &'r Image {
        match resource {
            Resource::Image(i) => i,
            Resource::Buffer(_) => unreachable!("image handle names a buffer"),
        }
    }
}

impl<'g, 'r> PassBuilder<'g, 'r> {
    fn declare<H: Handle>(&mut self, handle: &H, access: Access) -> &'r H::Target {
        // Several reads of one resource are fine (a vertex buffer also read as storage); a
        // write, or two image layouts, must be one combined declaration.
        let clash = self.uses.iter().any(|&(id, prev)| {
            id == handle.id()
                && (prev.info().writes
                    || access.info().writes
                    || (matches!(self.graph.resources[id], Resource::Image(_))
                        && prev.info().layout != access.info().layout))
        });
        assert!(
            !clash,
            "pass {}: conflicting declarations of one resource; declare its combined use once (e.g. ComputeReadWrite)",
            self.name
        );
        self.uses.push((handle.id(), access));
        H::resolve(&self.graph.resources[handle.id()])
    }

    /// Declares a read. Panics if `access` writes: that is a bug in the pass.
    pub fn read<H: Handle>(&mut self, handle: &H, access: Access) -> &'r H::Target {
        assert!(!access.info().writes, "pass {}: read() with writing access {access:?}", self.name);
        self.declare(handle, access)
    }

    /// Declares a write (or read-write); the handle is borrowed mutably to show it changes.
    pub fn write<H: Handle>(&mut self, handle: &mut H, access: Access) -> &'r H::Target {
        assert!(access.info().writes, "pass {}: write() with read-only access {access:?}", self.name);
        self.declare(handle, access)
    }

    /// Ends the declaration with the commands the pass records.
    pub fn record(self, record: impl FnOnce(&mut Cmd<'_>) -> Result<()> + 'r) {
        self.graph.passes.push(Pass { name: self.name, uses: self.uses, record: Box::new(record) });
    }
}
