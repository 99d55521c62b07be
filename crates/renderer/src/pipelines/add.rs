//! A compute pass added to a frame in one call: its definition starts the pass under its own
//! name, declares the resources it is given (its own group, then the shared groups `extra`
//! declares), and dispatches its pipeline. The definition's type names its own group and push
//! constants, so resources of another group or constants of another type do not compile.

use leakless_device::PushConstants;
use leakless_graph::{BindingGroup, Bindings, DeclareBindings, Graph, PassBuilder, PassName, Stage};

use crate::passes::photon_dispatch::PhotonDispatch;
use crate::pipelines::ComputePass;

/// How large a pass's dispatch is.
#[derive(Clone, Copy)]
pub enum Threads<'d> {
    /// Invocations along each axis.
    Fixed([u32; 3]),
    /// The workgroups a photon dispatch pass wrote (never more than its capacity needs).
    Indirect(&'d PhotonDispatch),
}

impl<B: BindingGroup + 'static, P: PushConstants> ComputePass<B, P> {
    /// Adds the pass with its own bindings only, over `threads` invocations.
    pub fn add<'r, R: DeclareBindings<Bindings = B>>(
        &self,
        graph: &mut Graph<'r>,
        resources: R,
        push: P,
        threads: [u32; 3],
    ) {
        self.record(graph.pass(self.name), resources, |_| (), push, Threads::Fixed(threads));
    }

    /// Adds the pass with its own bindings and the shared groups `extra` declares (the frame
    /// and lights, the G-buffer).
    pub fn add_with<'r, R: DeclareBindings<Bindings = B>, E: Bindings + 'r>(
        &self,
        graph: &mut Graph<'r>,
        resources: R,
        extra: impl FnOnce(&mut PassBuilder<'_, 'r>) -> E,
        push: P,
        threads: Threads<'_>,
    ) {
        self.record(graph.pass(self.name), resources, extra, push, threads);
    }

    /// Adds the pass under another label: `name`, numbered `index` where a frame repeats it
    /// ("sort histogram 2"), or the label of a caller that runs this pass's shader for its own
    /// ends (the scan of each photon ordering).
    #[allow(clippy::too_many_arguments)]
    pub fn add_as<'r, R: DeclareBindings<Bindings = B>, E: Bindings + 'r>(
        &self,
        graph: &mut Graph<'r>,
        (name, index): (PassName, Option<u32>),
        resources: R,
        extra: impl FnOnce(&mut PassBuilder<'_, 'r>) -> E,
        push: P,
        threads: Threads<'_>,
    ) {
        let pass = match index {
            Some(index) => graph.pass_numbered(name, index),
            None => graph.pass(name),
        };
        self.record(pass.runs(self.name), resources, extra, push, threads);
    }

    fn record<'r, R: DeclareBindings<Bindings = B>, E: Bindings + 'r>(
        &self,
        mut pass: PassBuilder<'_, 'r>,
        resources: R,
        extra: impl FnOnce(&mut PassBuilder<'_, 'r>) -> E,
        push: P,
        threads: Threads<'_>,
    ) {
        let own = resources.declare_on(&mut pass, Stage::Compute);
        let extra = extra(&mut pass);
        match threads {
            Threads::Fixed(threads) => pass.dispatch((own, extra), push, threads),
            Threads::Indirect(dispatch) => {
                let args = dispatch.declare(&mut pass);
                pass.dispatch_indirect((own, extra), push, args, dispatch.most_threads());
            }
        }
    }
}
