//! `Scene::load`: parse, validate, walk the node tree, gather what §4 keeps.

use std::path::Path;

use glam::{Mat4, Quat, Vec3};
use gltf::json;

use crate::accessor::Data;
use crate::animation::{self, Channel, Rig, Slot};
use crate::ignored::{counted, Ignored};
use crate::instance::{self, Instance};
use crate::material::{self, Material};
use crate::mesh::{Geometry, MeshError};
use crate::uri::{self, SourceError};
use crate::{camera, light, Scene, SceneError};

/// Required extensions that only change appearance in ways this renderer ignores
/// anyway; a file requiring them still loads (with the ignored line saying so).
fn ignorable_required(ext: &str) -> bool {
    ext.starts_with("KHR_materials_") || ext == "KHR_texture_transform"
}

pub(crate) fn load(path: &Path) -> Result<Scene, SceneError> {
    let bytes = std::fs::read(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => SceneError::NotFound { path: path.into() },
        _ => SceneError::Read { path: path.into(), source: e },
    })?;
    let name = path.file_stem().map_or_else(|| "scene".to_string(), |s| s.to_string_lossy().into_owned());
    let Parsed { root, blob, waived } = parse(path, &bytes)?;
    let base = path.parent().unwrap_or(Path::new("."));
    let buffers = uri::load_buffers(&root, blob, base).map_err(|(i, e)| match e {
        SourceError::Io(file, source) if source.kind() == std::io::ErrorKind::NotFound => {
            SceneError::Buffer { path: path.into(), message: format!("buffer {i}: file {} not found", file.display()) }
        }
        e => SceneError::Buffer { path: path.into(), message: format!("buffer {i}: {e}") },
    })?;
    let data = Data { root: &root, buffers: &buffers };
    let mut ignored = Ignored::scan(&root, &waived);
    let material::Loaded { mut materials, textures, warnings: material_warnings } = material::load(&root, &data, base)
        .map_err(|e| SceneError::Image { path: path.into(), index: e.index, message: e.message })?;
    let animation::Loaded { channels, ignored: ignored_channels } = animation::load(&root, &data).map_err(|e| {
        SceneError::Animation { path: path.into(), animation: e.animation, channel: e.channel, message: e.message }
    })?;
    for item in ignored_channels {
        ignored.add(item);
    }
    let mut targets = vec![Vec::new(); root.nodes.len()];
    for (i, c) in channels.iter().enumerate() {
        targets[c.target].push(i);
    }

    let mut walk = Walk {
        geometry: Geometry::default(),
        camera: None,
        lights: Vec::new(),
        warnings: Vec::new(),
        further_cameras: 0,
        channels,
        targets,
        rig: Rig::default(),
        instances: Vec::new(),
    };
    let scene = root.scene.and_then(|i| root.scenes.get(i.value())).or(root.scenes.first());
    let roots: Vec<usize> = match scene {
        Some(s) => s.nodes.iter().map(|n| n.value()).collect(),
        // No scene at all: render every parentless node, as viewers do.
        None => parentless(&root),
    };
    let file_materials = materials.len();
    let mut default_material = None;
    walk.nodes(&root, &data, &roots, |m| match m {
        Some(i) if i < file_materials => i as u32,
        _ => *default_material.get_or_insert_with(|| {
            materials.push(Material::default_white());
            (materials.len() - 1) as u32
        }),
    })
    .map_err(|(mesh, e)| match e {
        MeshError::Buffer(message) => {
            SceneError::Buffer { path: path.into(), message: format!("mesh {mesh}: {message}") }
        }
        MeshError::NonFinite => SceneError::NonFinitePosition { name: name.clone(), mesh },
    })?;
    if materials.is_empty() {
        materials.push(Material::default_white());
    }
    counted(&mut ignored, walk.further_cameras, "further camera");

    let mut g = walk.geometry;
    let rig = walk.rig;
    // Animated mesh nodes' triangles follow the static ones, placed at t = 0 by
    // the same function a renderer calls per frame.
    let mut instances = Vec::with_capacity(walk.instances.len());
    let world = if walk.instances.is_empty() { Vec::new() } else { rig.world_at(0.0) };
    // Every pose the animation reaches must stay finite: checked at the times the bounds
    // sample (every key and points between), beyond t = 0.
    let poses: Vec<Vec<glam::Mat4>> = rig.bounds_times().into_iter().map(|t| rig.world_at(t)).collect();
    for p in walk.instances {
        let vertices = instance::world_vertices(&p.local_vertices, &world[p.slot]);
        let finite =
            |vs: &[crate::Vertex]| vs.iter().all(|v| v.position.iter().chain(&v.normal).all(|x| x.is_finite()));
        if !finite(&vertices) || poses.iter().any(|w| !finite(&instance::world_vertices(&p.local_vertices, &w[p.slot])))
        {
            return Err(SceneError::NonFinitePosition { name, mesh: p.mesh });
        }
        let first_triangle = g.triangle_material.len() as u32;
        let triangle_count = p.materials.len() as u32;
        g.vertices.extend(vertices);
        g.triangle_material.extend(p.materials);
        instances.push(Instance {
            name: p.name,
            first_triangle,
            triangle_count,
            local_vertices: p.local_vertices,
            slot: p.slot,
        });
    }
    if g.vertices.is_empty() {
        return Err(SceneError::NoTriangles { name });
    }
    // A light is a punctual light or a triangle whose material emits.
    let emissive = |m: &u32| materials.get(*m as usize).is_some_and(|m| m.emits());
    if walk.lights.is_empty() && !g.triangle_material.iter().any(emissive) {
        return Err(SceneError::NoLight { name });
    }
    let mut warnings: Vec<String> = ignored.line().into_iter().collect();
    warnings.extend(material_warnings);
    if !g.skipped_modes.is_empty() {
        let modes: Vec<String> = g.skipped_modes.iter().map(|(m, n)| format!("{n} {m}")).collect();
        warnings.push(format!("skipped primitives that are not triangles: {}", modes.join(", ")));
    }
    if g.without_positions > 0 {
        warnings.push(format!("skipped {} primitive(s) without POSITION", g.without_positions));
    }
    if g.ragged_indices > 0 {
        warnings.push(format!(
            "{} triangle primitive(s) have an index count that is not a multiple of 3: extra indices dropped",
            g.ragged_indices
        ));
    }
    warnings.extend(walk.warnings);
    let extras = scene.and_then(|s| s.extras.as_ref()).map(|r| r.get().to_string());
    Ok(Scene {
        name,
        vertices: g.vertices,
        triangle_material: g.triangle_material,
        materials,
        textures,
        camera: walk.camera,
        lights: walk.lights,
        warnings,
        extras,
        instances,
        rig,
    })
}

/// A parsed and validated document.
struct Parsed {
    root: json::Root,
    /// The GLB `BIN` chunk.
    blob: Option<Vec<u8>>,
    /// Required extensions that were waived (see [`ignorable_required`]).
    waived: Vec<String>,
}

/// Parses and validates the document.
fn parse(path: &Path, bytes: &[u8]) -> Result<Parsed, SceneError> {
    let malformed = |message: String| SceneError::Malformed { path: path.into(), message };
    if bytes.starts_with(b"glTF") {
        // gltf 1.4 computes `length - 12` unchecked: guard the subtraction.
        let declared = bytes
            .get(8..12)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .ok_or_else(|| malformed("GLB header is truncated".into()))?;
        if declared < 12 || declared as usize > bytes.len() {
            return Err(malformed(format!(
                "GLB header declares {declared} bytes but the file has {} (truncated?)",
                bytes.len()
            )));
        }
    }
    let gltf = gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| malformed(e.to_string()))?;
    let blob = gltf.blob;
    let mut root = gltf.document.into_json();
    let mut waived = Vec::new();
    let mut unsupported = Vec::new();
    root.extensions_required.retain(|ext| {
        if json::extensions::ENABLED_EXTENSIONS.contains(&ext.as_str()) {
            true
        } else if ext == "KHR_mesh_quantization" || ignorable_required(ext) {
            waived.push(ext.clone());
            false
        } else {
            unsupported.push(ext.clone());
            false
        }
    });
    if !unsupported.is_empty() {
        return Err(SceneError::Unsupported {
            path: path.into(),
            message: format!("the file requires extension(s) {}", unsupported.join(", ")),
        });
    }
    validate(&root).map_err(malformed)?;
    Ok(Parsed { root, blob, waived })
}

/// glTF validation (dangling indices, invalid enum values, missing fields), with
/// two adjustments to `gltf`'s own:
/// * its POSITION hook indexes the accessor array unchecked, so that index is
///   checked first (a dangling one would panic inside `gltf-json`);
/// * POSITION `min`/`max` are not required: the spec asks for them but this loader
///   never reads them, and viewers accept files without them.
fn validate(root: &json::Root) -> Result<(), String> {
    use json::validation::{Checked, Validate};
    for (mi, mesh) in root.meshes.iter().enumerate() {
        for (pi, prim) in mesh.primitives.iter().enumerate() {
            let position = prim.attributes.get(&Checked::Valid(json::mesh::Semantic::Positions));
            if position.is_some_and(|a| a.value() >= root.accessors.len()) {
                return Err(format!("meshes[{mi}].primitives[{pi}].attributes[\"POSITION\"]: Index out of bounds"));
            }
        }
    }
    let mut errors = Vec::new();
    root.validate(root, json::Path::new, &mut |path, error| {
        let path = path();
        let p = path.as_str();
        if !(p.ends_with("[\"POSITION\"].min") || p.ends_with("[\"POSITION\"].max")) {
            errors.push(format!("{p}: {error}"));
        }
    });
    match errors.len() {
        0 => Ok(()),
        n if n <= 3 => Err(errors.join("; ")),
        n => Err(format!("{} (and {} more)", errors[..3].join("; "), n - 3)),
    }
}

/// Nodes that no node lists as a child.
fn parentless(root: &json::Root) -> Vec<usize> {
    let mut is_child = vec![false; root.nodes.len()];
    for n in &root.nodes {
        for c in n.children.iter().flatten() {
            if let Some(flag) = is_child.get_mut(c.value()) {
                *flag = true;
            }
        }
    }
    (0..root.nodes.len()).filter(|&i| !is_child[i]).collect()
}

/// State of the node walk.
struct Walk {
    geometry: Geometry,
    camera: Option<crate::Camera>,
    lights: Vec<crate::Light>,
    warnings: Vec<String>,
    further_cameras: usize,
    /// Every valid channel in the file, and for each node the indices of those
    /// driving it; the walk moves those of placed nodes into `rig`.
    channels: Vec<Channel>,
    targets: Vec<Vec<usize>>,
    rig: Rig,
    instances: Vec<PendingInstance>,
}

/// An animated mesh node's triangles, in mesh space, until the walk is done.
struct PendingInstance {
    name: String,
    /// The mesh's label for errors.
    mesh: String,
    slot: usize,
    local_vertices: Vec<crate::Vertex>,
    materials: Vec<u32>,
}

impl Walk {
    /// Depth-first, pre-order, children in file order ("traversal order" for the
    /// first camera). Iterative, and each node is visited once, so a deep or cyclic
    /// (invalid) hierarchy cannot overflow the stack or loop.
    fn nodes(
        &mut self,
        root: &json::Root,
        data: &Data,
        roots: &[usize],
        mut material: impl FnMut(Option<usize>) -> u32,
    ) -> Result<(), (String, MeshError)> {
        let mut visited = vec![false; root.nodes.len()];
        let mut revisits = 0usize;
        // (node, parent's world transform, parent's rig slot)
        let mut stack: Vec<(usize, Mat4, Option<usize>)> =
            roots.iter().rev().map(|&n| (n, Mat4::IDENTITY, None)).collect();
        while let Some((index, parent, parent_slot)) = stack.pop() {
            let Some(node) = root.nodes.get(index) else {
                continue;
            };
            if std::mem::replace(&mut visited[index], true) {
                revisits += 1;
                continue;
            }
            let slot = self.rig.slots.len();
            let mut channels = Vec::new();
            for &c in &self.targets[index] {
                let mut ch = self.channels[c].clone();
                ch.target = slot;
                channels.push(self.rig.channels.len());
                self.rig.channels.push(ch);
            }
            let animated = !channels.is_empty() || parent_slot.is_some_and(|p| self.rig.slots[p].animated);
            let rest = animation::rest_trs(node);
            self.rig.slots.push(Slot { parent: parent_slot, local: local_matrix(node), rest, channels, animated });
            // Without channels this is `parent * local_matrix(node)`.
            let world = parent * self.rig.local_at(slot, 0.0);
            let mesh = node.mesh.map(|m| m.value());
            if let Some((mi, mesh)) = mesh.and_then(|mi| root.meshes.get(mi).map(|m| (mi, m))) {
                let label = || match &mesh.name {
                    Some(n) => format!("{mi} '{n}'"),
                    None => mi.to_string(),
                };
                if animated {
                    // Mesh space now; placed after the walk (see `load`).
                    let (v0, t0) = (self.geometry.vertices.len(), self.geometry.triangle_material.len());
                    self.geometry.append(mesh, Mat4::IDENTITY, data, &mut material).map_err(|e| (label(), e))?;
                    let local_vertices = self.geometry.vertices.split_off(v0);
                    let materials = self.geometry.triangle_material.split_off(t0);
                    if !materials.is_empty() {
                        let name =
                            node.name.clone().or_else(|| mesh.name.clone()).unwrap_or_else(|| format!("node {index}"));
                        self.instances.push(PendingInstance { name, mesh: label(), slot, local_vertices, materials });
                    }
                } else {
                    self.geometry.append(mesh, world, data, &mut material).map_err(|e| (label(), e))?;
                }
            }
            let camera = node.camera.map(|c| c.value());
            if let Some((ci, cam)) = camera.and_then(|ci| root.cameras.get(ci).map(|c| (ci, c))) {
                if self.camera.is_some() {
                    self.further_cameras += 1;
                } else {
                    match camera::from_json(ci, cam, world) {
                        Ok(c) => {
                            if animated {
                                self.rig.camera = Some((slot, ci, cam.clone()));
                            }
                            self.camera = Some(c);
                        }
                        Err(w) => self.warnings.push(w),
                    }
                }
            }
            let light_index =
                node.extensions.as_ref().and_then(|e| e.khr_lights_punctual.as_ref()).map(|l| l.light.value());
            if let Some(li) = light_index {
                let def = root
                    .extensions
                    .as_ref()
                    .and_then(|e| e.khr_lights_punctual.as_ref())
                    .and_then(|l| l.lights.get(li));
                match def.map(|d| light::from_json(li, d, world)) {
                    Some(Ok(l)) => {
                        if let (true, Some(d)) = (animated, def) {
                            self.rig.lights.push((self.lights.len(), slot, li, d.clone()));
                        }
                        self.lights.push(l);
                    }
                    Some(Err(w)) => self.warnings.push(w),
                    None => self.warnings.push(format!("node {index} references missing light {li}")),
                }
            }
            for c in node.children.iter().flatten().rev() {
                stack.push((c.value(), world, Some(slot)));
            }
        }
        if revisits > 0 {
            self.warnings.push(format!(
                "{revisits} node reference(s) repeat a node already placed (glTF node trees must be disjoint): skipped"
            ));
        }
        Ok(())
    }
}

/// The node's local transform: its matrix, or T·R·S. A zero or non-finite rotation
/// quaternion is replaced by the identity rather than poisoning every vertex.
fn local_matrix(node: &json::scene::Node) -> Mat4 {
    if let Some(m) = node.matrix {
        return Mat4::from_cols_array(&m);
    }
    let t = Vec3::from(node.translation.unwrap_or([0.0; 3]));
    let s = Vec3::from(node.scale.unwrap_or([1.0; 3]));
    let q = node.rotation.as_ref().map_or(Quat::IDENTITY, |r| Quat::from_array(r.0));
    let q = if q.is_finite() && q.length_squared() > 0.0 { q.normalize() } else { Quat::IDENTITY };
    Mat4::from_scale_rotation_translation(s, q, t)
}
