//! Compute pipelines by pass name, lent to a frame's graph (kajiya's pipeline cache): a pass
//! function asks the graph for its pipeline, so it owns none and a new pass needs no field in
//! the renderer. The renderer fills one table per trace backend; a table shares the pipelines
//! that do not depend on the backend with the other's.

use std::collections::HashMap;
use std::rc::Rc;

use leakless_device::ComputePipeline;

use crate::name::PassName;

/// Compute pipelines keyed by the label of the pass that made them.
#[derive(Default)]
pub struct PipelineTable {
    by_label: HashMap<&'static str, Rc<ComputePipeline>>,
}

impl PipelineTable {
    /// Adds `pipeline` under `name`; false when the table already had one there.
    pub fn insert(&mut self, name: PassName, pipeline: Rc<ComputePipeline>) -> bool {
        self.by_label.insert(name.label, pipeline).is_none()
    }

    pub fn contains(&self, name: PassName) -> bool {
        self.by_label.contains_key(name.label)
    }

    pub fn contains_label(&self, label: &str) -> bool {
        self.by_label.contains_key(label)
    }

    pub fn get(&self, name: PassName) -> Option<&ComputePipeline> {
        self.by_label.get(name.label).map(|p| &**p)
    }

    pub fn len(&self) -> usize {
        self.by_label.len()
    }

    pub fn is_empty(&self) -> bool {
        self.by_label.is_empty()
    }
}
