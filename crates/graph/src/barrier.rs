//! Barrier derivation, independent of any device: given how a resource was last used and how
//! the next pass uses it, which dependency (if any) must separate them.

use ash::vk;
use leakless_device::sync::Access;

/// A dependency between earlier and later uses of one resource.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Transition {
    pub src_stage: vk::PipelineStageFlags2,
    pub src_access: vk::AccessFlags2,
    pub dst_stage: vk::PipelineStageFlags2,
    pub dst_access: vk::AccessFlags2,
    /// Both `UNDEFINED` for buffers.
    pub old_layout: vk::ImageLayout,
    pub new_layout: vk::ImageLayout,
}

/// What the graph remembers of one resource while it walks the passes.
#[derive(Clone, Debug)]
pub struct ResourceState {
    is_image: bool,
    layout: vk::ImageLayout,
    /// Stages and accesses of the last write (a layout transition counts as a write made
    /// available by its own barrier, so its access mask is empty).
    write_stage: vk::PipelineStageFlags2,
    write_access: vk::AccessFlags2,
    /// Reads since that write, each already made visible.
    readers: Vec<Access>,
    /// Stages of earlier frames that may still be reading the resource (frames in flight):
    /// its first write in this frame waits for them.
    earlier_frames: vk::PipelineStageFlags2,
}

impl ResourceState {
    /// A buffer; `written_before` when an earlier execution wrote it on the device.
    pub fn buffer(written_before: bool) -> Self {
        let mut state = Self::new(false, vk::ImageLayout::UNDEFINED);
        if written_before {
            state.write_stage = vk::PipelineStageFlags2::ALL_COMMANDS;
            state.write_access = vk::AccessFlags2::MEMORY_WRITE;
        }
        state
    }

    /// A buffer that frames share (imported, or kept in the pool from frame to frame), while
    /// the frame before may still be running. Once written on the device, the last write
    /// already makes a later write wait for everything before it; a buffer the host filled
    /// (scene data, later updated by a copy) has no such write, so its first write waits for
    /// every earlier command instead, and its reads wait for nothing.
    pub fn shared_buffer(written_before: bool) -> Self {
        let mut state = Self::buffer(written_before);
        if !written_before {
            state.earlier_frames = vk::PipelineStageFlags2::ALL_COMMANDS;
        }
        state
    }

    /// Whether any use so far wrote the resource.
    pub fn written(&self) -> bool {
        self.write_access != vk::AccessFlags2::NONE
    }

    /// An image whose contents are discarded and whose first use must come after `stage`
    /// (a swapchain image after the acquire semaphore's wait stage).
    pub fn acquired_image(stage: vk::PipelineStageFlags2) -> Self {
        let mut state = Self::new(true, vk::ImageLayout::UNDEFINED);
        state.write_stage = stage;
        state
    }

    /// An image in `layout`, as left by an earlier graph execution (or `UNDEFINED`).
    pub fn image(layout: vk::ImageLayout) -> Self {
        Self::new(true, layout)
    }

    fn new(is_image: bool, layout: vk::ImageLayout) -> Self {
        // Work from an earlier submission is ordered before this one on the queue, but its
        // writes still need making visible: treat them as one write by any stage.
        let (write_stage, write_access) = if layout == vk::ImageLayout::UNDEFINED {
            (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE)
        } else {
            (vk::PipelineStageFlags2::ALL_COMMANDS, vk::AccessFlags2::MEMORY_WRITE)
        };
        let earlier_frames = vk::PipelineStageFlags2::NONE;
        ResourceState { is_image, layout, write_stage, write_access, readers: Vec::new(), earlier_frames }
    }

    pub fn layout(&self) -> vk::ImageLayout {
        self.layout
    }

    /// Records the use `next` and returns the dependency it needs, if any.
    pub fn access(&mut self, next: Access) -> Option<Transition> {
        let n = next.info();
        let new_layout = if self.is_image { n.layout } else { vk::ImageLayout::UNDEFINED };
        let layout_change = self.is_image && new_layout != self.layout;

        if !n.writes && !layout_change {
            // Read after read: nothing to do when an earlier read of the same kind already saw
            // the last write; otherwise make the write visible to this reader too.
            if self.readers.contains(&next) {
                return None;
            }
            self.readers.push(next);
            if self.write_stage == vk::PipelineStageFlags2::NONE {
                return None;
            }
            return Some(Transition {
                src_stage: self.write_stage,
                src_access: self.write_access,
                dst_stage: n.stage,
                dst_access: n.access,
                old_layout: self.layout,
                new_layout,
            });
        }

        // A write or a layout change waits for the last write and for every read since it.
        let reader_stages = self.readers.iter().fold(vk::PipelineStageFlags2::NONE, |s, r| s | r.info().stage);
        let src_stage = self.write_stage | reader_stages | self.earlier_frames;
        self.earlier_frames = vk::PipelineStageFlags2::NONE;
        let transition = (src_stage != vk::PipelineStageFlags2::NONE || layout_change).then_some(Transition {
            src_stage,
            src_access: self.write_access,
            dst_stage: n.stage,
            dst_access: n.access,
            old_layout: self.layout,
            new_layout,
        });
        self.layout = new_layout;
        self.readers.clear();
        if n.writes {
            self.write_stage = n.stage;
            self.write_access = n.access & WRITE_BITS;
        } else {
            // The transition is the write; this read already sees it.
            self.write_stage = n.stage;
            self.write_access = vk::AccessFlags2::NONE;
            self.readers.push(next);
        }
        transition
    }
}

/// The access bits that denote writes (what an availability operation must cover).
const WRITE_BITS: vk::AccessFlags2 = vk::AccessFlags2::from_raw(
    vk::AccessFlags2::SHADER_STORAGE_WRITE.as_raw()
        | vk::AccessFlags2::COLOR_ATTACHMENT_WRITE.as_raw()
        | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw()
        | vk::AccessFlags2::TRANSFER_WRITE.as_raw()
        | vk::AccessFlags2::HOST_WRITE.as_raw()
        | vk::AccessFlags2::ACCELERATION_STRUCTURE_WRITE_KHR.as_raw()
        | vk::AccessFlags2::MEMORY_WRITE.as_raw(),
);

#[cfg(test)]
mod tests {
    use super::*;
    use vk::AccessFlags2 as A;
    use vk::ImageLayout as L;
    use vk::PipelineStageFlags2 as S;

    #[test]
    fn first_write_to_a_fresh_buffer_needs_no_barrier() {
        let mut b = ResourceState::buffer(false);
        assert_eq!(b.access(Access::ComputeWrite), None);
    }

    #[test]
    fn a_shared_buffer_the_host_filled_waits_for_earlier_frames_before_its_first_write_only() {
        let mut b = ResourceState::shared_buffer(false);
        assert_eq!(b.access(Access::ComputeRead), None, "host data needs no barrier to be read");
        let t = b.access(Access::TransferWrite).expect("a frame in flight may still read it");
        assert_eq!((t.src_stage, t.src_access), (S::ALL_COMMANDS | S::COMPUTE_SHADER, A::NONE));
        let t = b.access(Access::ComputeRead).expect("RAW");
        assert_eq!((t.src_stage, t.src_access), (S::TRANSFER, A::TRANSFER_WRITE));
        let t = b.access(Access::TransferWrite).expect("WAR within the frame");
        assert_eq!(t.src_stage, S::TRANSFER | S::COMPUTE_SHADER, "earlier frames were waited for once");
        // Written on the device before: the usual state already orders everything.
        assert_eq!(
            ResourceState::shared_buffer(true).access(Access::TransferWrite).map(|t| t.src_stage),
            Some(S::ALL_COMMANDS)
        );
    }

    #[test]
    fn read_after_write_makes_the_write_visible_once_per_kind_of_reader() {
        let mut b = ResourceState::buffer(false);
        b.access(Access::ComputeWrite);
        let t = b.access(Access::ComputeRead).expect("RAW needs a barrier");
        assert_eq!((t.src_stage, t.src_access), (S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE));
        assert_eq!(t.dst_stage, S::COMPUTE_SHADER);
        assert!(t.dst_access.contains(A::SHADER_STORAGE_READ));
        assert_eq!(b.access(Access::ComputeRead), None, "second compute read is covered");
        let t = b.access(Access::TransferRead).expect("a new kind of reader needs visibility");
        assert_eq!(t.src_access, A::SHADER_STORAGE_WRITE);
        assert_eq!(t.dst_stage, S::TRANSFER);
    }

    #[test]
    fn an_indirect_dispatch_waits_for_the_shader_that_wrote_its_arguments() {
        let mut b = ResourceState::buffer(false);
        b.access(Access::ComputeWrite);
        let t = b.access(Access::IndirectCommandRead).expect("the command must be visible to the indirect read");
        assert_eq!((t.src_stage, t.src_access), (S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE));
        assert_eq!((t.dst_stage, t.dst_access), (S::DRAW_INDIRECT, A::INDIRECT_COMMAND_READ));
        assert_eq!(b.access(Access::IndirectCommandRead), None, "a second indirect read is covered");
        let t = b.access(Access::ComputeWrite).expect("the next write waits for the indirect reads");
        assert!(t.src_stage.contains(S::DRAW_INDIRECT));
    }

    #[test]
    fn write_after_reads_waits_for_every_reader_without_access_masks() {
        let mut b = ResourceState::buffer(false);
        b.access(Access::TransferWrite);
        b.access(Access::ComputeRead);
        b.access(Access::VertexBuffer);
        let t = b.access(Access::TransferWrite).expect("WAR needs an execution dependency");
        assert_eq!(t.src_stage, S::TRANSFER | S::COMPUTE_SHADER | S::VERTEX_ATTRIBUTE_INPUT);
        assert_eq!(t.src_access, A::TRANSFER_WRITE);
    }

    #[test]
    fn image_layouts_follow_the_accesses() {
        let mut i = ResourceState::image(L::UNDEFINED);
        let t = i.access(Access::ColorAttachmentWrite).expect("initial transition");
        assert_eq!((t.old_layout, t.new_layout), (L::UNDEFINED, L::COLOR_ATTACHMENT_OPTIMAL));
        assert_eq!(t.src_stage, S::NONE);
        let t = i.access(Access::ComputeRead).expect("attachment → general");
        assert_eq!((t.old_layout, t.new_layout), (L::COLOR_ATTACHMENT_OPTIMAL, L::GENERAL));
        assert_eq!((t.src_stage, t.src_access), (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE));
        assert_eq!(i.access(Access::ComputeRead), None);
        let t = i.access(Access::TransferRead).expect("general → transfer src");
        assert_eq!((t.old_layout, t.new_layout), (L::GENERAL, L::TRANSFER_SRC_OPTIMAL));
        // The attachment write was already waited for by the previous transition; chaining
        // through the compute readers covers it.
        assert_eq!((t.src_stage, t.src_access), (S::COMPUTE_SHADER, A::NONE), "waits for the readers");
        assert_eq!(i.layout(), L::TRANSFER_SRC_OPTIMAL);
        // After a transition done for a read, another reader kind in the same layout still
        // gets a dependency on that transition.
        let t = i.access(Access::HostRead);
        assert!(t.is_some(), "host read of the image after a transition: layout differs → transition");
    }

    #[test]
    fn image_kept_across_executions_is_not_discarded() {
        let mut i = ResourceState::image(L::GENERAL);
        let t = i.access(Access::ComputeReadWrite).expect("previous frame's writes must be visible");
        assert_eq!(t.old_layout, L::GENERAL, "no UNDEFINED: the accumulated content is kept");
        assert_eq!(t.src_access, A::MEMORY_WRITE);
    }

    #[test]
    fn an_acquired_swapchain_image_waits_for_the_acquire_stage() {
        let mut i = ResourceState::acquired_image(S::COLOR_ATTACHMENT_OUTPUT);
        let t = i.access(Access::ColorAttachmentWrite).expect("discard transition");
        assert_eq!((t.old_layout, t.new_layout), (L::UNDEFINED, L::COLOR_ATTACHMENT_OPTIMAL));
        // Chained to the semaphore wait: the transition cannot run before the image is ready.
        assert_eq!((t.src_stage, t.src_access), (S::COLOR_ATTACHMENT_OUTPUT, A::NONE));
        i.access(Access::ColorAttachmentWrite).expect("overlay after tonemap: write after write");
        let t = i.access(Access::Present).expect("to the presentation layout");
        assert_eq!((t.old_layout, t.new_layout), (L::COLOR_ATTACHMENT_OPTIMAL, L::PRESENT_SRC_KHR));
        assert_eq!(t.src_access, A::COLOR_ATTACHMENT_WRITE);
    }

    #[test]
    fn buffer_written_by_an_earlier_execution_is_made_visible() {
        let mut b = ResourceState::buffer(true);
        let t = b.access(Access::RayQueryRead).expect("earlier device writes need visibility");
        assert_eq!((t.src_stage, t.src_access), (S::ALL_COMMANDS, A::MEMORY_WRITE));
        assert_eq!(ResourceState::buffer(false).access(Access::RayQueryRead), None);
    }

    #[test]
    fn write_after_write_orders_both_writes() {
        let mut b = ResourceState::buffer(false);
        b.access(Access::ComputeWrite);
        let t = b.access(Access::ComputeWrite).expect("WAW");
        assert_eq!((t.src_access, t.dst_access), (A::SHADER_STORAGE_WRITE, A::SHADER_STORAGE_WRITE));
    }
}
