//! A compute pass added to a frame in one call: its definition starts the pass under its own
//! name, declares the resources it is given (its own group, then the shared groups `extra`
//! declares), and dispatches its pipeline. The resources' type says which bindings they are
//! ([`DeclareBindings`]); debug builds check that the definition binds that group and pushes
//! constants of the size given.

use bytemuck::NoUninit;
use leakless_graph::{Bindings, DeclareBindings, Graph, PassBuilder, PassName, Stage};

use crate::passes::photon_dispatch::PhotonDispatch;
use crate::pipelines::ComputePassDef;

/// How large a pass's dispatch is.
#[derive(Clone, Copy)]
pub enum Threads<'d> {
    /// Invocations along each axis.
    Fixed([u32; 3]),
    /// The workgroups a photon dispatch pass wrote (never more than its capacity needs).
    Indirect(&'d PhotonDispatch),
}

/// Resources of a pass's own group, whose bindings live as long as the frame's graph.
pub trait OwnResources<'r>: DeclareBindings<Bindings: 'r> {}
impl<'r, R: DeclareBindings<Bindings: 'r>> OwnResources<'r> for R {}

impl ComputePassDef {
    /// Adds the pass with its own bindings only, over `threads` invocations.
    pub fn add<'r, R: OwnResources<'r>, P: NoUninit + 'r>(
        &self,
        graph: &mut Graph<'r>,
        resources: R,
        push: P,
        threads: [u32; 3],
    ) {
        self.record(graph.pass(self.name), resources, |_| (), push, Threads::Fixed(threads));
    }

    /// Adds the pass with its own bindings and the shared groups `extra` declares (the
    /// G-buffer, the scene, the trace structures).
    pub fn add_with<'r, R: OwnResources<'r>, E: Bindings + 'r, P: NoUninit + 'r>(
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
    pub fn add_as<'r, R: OwnResources<'r>, E: Bindings + 'r, P: NoUninit + 'r>(
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

    fn record<'r, R: OwnResources<'r>, E: Bindings + 'r, P: NoUninit + 'r>(
        &self,
        mut pass: PassBuilder<'_, 'r>,
        resources: R,
        extra: impl FnOnce(&mut PassBuilder<'_, 'r>) -> E,
        push: P,
        threads: Threads<'_>,
    ) {
        debug_assert!(self.binds(R::DECLS), "pass {}: given resources of a group it does not bind", self.name);
        debug_assert_eq!(
            std::mem::size_of::<P>(),
            self.push.map_or(0, |l| l.size as usize),
            "pass {}: push constants of another size than its definition's",
            self.name
        );
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

    /// Whether one of the definition's groups is `decls` (by binding name, in order).
    fn binds(&self, decls: &[leakless_device::BindingDecl]) -> bool {
        let names = |g: &[leakless_device::BindingDecl]| g.iter().map(|d| d.name).collect::<Vec<_>>();
        self.bindings.iter().any(|group| names(group) == names(decls))
    }
}

#[cfg(test)]
mod tests {
    use crate::passes::compose::{ComposeBindings, COMPOSE};
    use crate::passes::scan::ScanBindings;

    /// The debug check that a pass is given resources of a group it binds tells the groups apart.
    #[test]
    fn a_pass_binds_its_own_group_and_not_another() {
        assert!(COMPOSE.binds(ComposeBindings::DECLS));
        assert!(!COMPOSE.binds(ScanBindings::DECLS));
    }
}
