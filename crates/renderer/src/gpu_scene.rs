//! The scene as the GPU sees it: vertex, material and texel buffers, uploaded once (the animated
//! instances' vertices are copied again whenever they move: `scene_pose.rs`). (Lights
//! are uploaded with every frame, so they can move: `photon_lights.rs`.)
//!
//! The corners' attributes go in one buffer each ([`VertexStreams`]): the largest, positions,
//! holds 36 bytes a triangle, so a storage-buffer range of 128 MiB (lavapipe's) binds 3.7M
//! triangles, where the 96-byte `Vertex` bound 1.4M.

use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use leakless_device::{gpu_struct, Buffer, Gpu, GpuStruct};
use leakless_graph::{shader_bindings, BufferHandle, Graph, PassBuilder, Stage};
use leakless_scene::{LightKind, Scene, Vertex};

use crate::device_address::address_words;
use crate::emitters::EmitterTable;
use crate::error::{RenderError, Result};
use crate::gpu_types::{self, Emitter, Light, Material};
use crate::trace::SceneBvh;

gpu_struct! {
    /// The `SceneAddresses` block of scene.glsl: the device addresses the shaders read the
    /// surfaces through (device_address.rs says why), each as a `uvec2`.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct SceneAddresses {
        pub positions: [u32; 2],
        pub normals: [u32; 2],
        pub uvs: [u32; 2],
        pub triangle_materials: [u32; 2],
        pub materials: [u32; 2],
        pub texels: [u32; 2],
    }
}

shader_bindings! {
    /// What `scene.glsl` binds: the surfaces, by triangle index, and their addresses.
    pub struct SceneBindings {
        vertex_positions: read array(f32::LAYOUT),
        vertex_normals: read array(f32::LAYOUT),
        vertex_uvs: read array(f32::LAYOUT),
        triangle_materials: read array(u32::LAYOUT),
        materials: read array(Material::LAYOUT),
        texels: read array(u32::LAYOUT),
        scene_addresses: read uniform(SceneAddresses::LAYOUT),
    }
    pub struct SceneResources;
}

shader_bindings! {
    /// What `emitters.glsl` binds: the emissive triangles and their NEE CDF.
    pub struct EmitterBindings {
        emitters: read array(Emitter::LAYOUT),
    }
    pub struct EmitterResources;
}

/// The G-buffer stores `triangle + 1` in a float channel, exact up to 2^24.
pub const MAX_TRIANGLES: usize = (1 << 24) - 1;

/// The corners of the scene's triangles, three a triangle in world space, split by attribute.
pub struct VertexStreams {
    /// x, y, z per corner.
    pub positions: Vec<[f32; 3]>,
    /// The unit shading normal per corner.
    pub normals: Vec<[f32; 3]>,
    /// Texture coordinates (set 0) per corner.
    pub uvs: Vec<[f32; 2]>,
}

impl VertexStreams {
    pub fn split(vertices: &[Vertex]) -> VertexStreams {
        VertexStreams {
            positions: vertices.iter().map(|v| v.position).collect(),
            normals: vertices.iter().map(|v| v.normal).collect(),
            uvs: vertices.iter().map(|v| v.uv).collect(),
        }
    }
}

/// The GPU buffers of [`VertexStreams`].
pub struct VertexBuffers {
    /// Also the ray-query BLAS's build input (12-byte stride).
    pub positions: Buffer,
    pub normals: Buffer,
    pub uvs: Buffer,
}

pub struct GpuScene {
    pub vertices: VertexBuffers,
    pub vertex_count: u32,
    /// One material index per triangle.
    pub triangle_materials: Buffer,
    pub materials: Buffer,
    /// Every texture's texels, RGBA8 packed in one word each.
    pub texels: Buffer,
    /// Per triangle, its coplanar neighbour across each edge (`Scene::coplanar_neighbours`),
    /// which the visible-disk pass walks instead of tracing rays down.
    pub coplanar_neighbours: Buffer,
    /// The BVH over `vertices` (the compute backend traverses it; every backend's clearance
    /// pass searches it) and the scene's trace scale.
    pub bvh: SceneBvh,
    /// The emissive triangles (`emitters.glsl`), and their table on the CPU.
    pub emitters: Buffer,
    pub emitter_table: EmitterTable,
    /// The pose version whose instance vertices `vertices` holds (`ScenePose::version`).
    pub placed_version: u64,
    /// The surfaces' device addresses (`SceneAddresses`).
    pub addresses: Buffer,
}

impl GpuScene {
    pub fn upload(gpu: &Gpu, scene: &Scene) -> Result<GpuScene> {
        if scene.triangle_count() > MAX_TRIANGLES {
            return Err(RenderError::Settings(format!(
                "scene {} has {} triangles; at most {MAX_TRIANGLES} are supported",
                scene.name,
                scene.triangle_count()
            )));
        }
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS;
        let mut position_usage = storage;
        if gpu.capabilities().acceleration_structure {
            position_usage |= vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR;
        }
        let streams = VertexStreams::split(&scene.vertices);
        let vertices = VertexBuffers {
            positions: Buffer::with_data(
                gpu,
                "vertex positions",
                position_usage,
                bytemuck::cast_slice(&streams.positions),
            )?,
            normals: Buffer::with_data(gpu, "vertex normals", storage, bytemuck::cast_slice(&streams.normals))?,
            uvs: Buffer::with_data(gpu, "vertex uvs", storage, bytemuck::cast_slice(&streams.uvs))?,
        };
        drop(streams);
        let triangle_materials =
            Buffer::with_data(gpu, "triangle materials", storage, bytemuck::cast_slice(&scene.triangle_material))?;

        let mut texels: Vec<u32> = Vec::new();
        let mut texture_offsets = Vec::with_capacity(scene.textures.len());
        for t in &scene.textures {
            texture_offsets.push(texels.len() as u32);
            texels.extend(t.texels.iter().map(|&rgba| u32::from_le_bytes(rgba)));
        }
        let materials: Vec<Material> = scene
            .materials
            .iter()
            .map(|m| {
                let slot = |t: Option<u32>| match t {
                    Some(i) => (
                        texture_offsets[i as usize],
                        scene.textures[i as usize].width,
                        scene.textures[i as usize].height,
                    ),
                    None => (0, 0, 0),
                };
                let (texture_offset, texture_width, texture_height) = slot(m.texture);
                let (emission_texture_offset, emission_texture_width, emission_texture_height) =
                    slot(m.emission_texture);
                Material {
                    base_color: m.base_color.to_array(),
                    texture_offset,
                    texture_width,
                    texture_height,
                    alpha_cutoff: m.alpha_cutoff.unwrap_or(-1.0),
                    emission: m.emission.to_array(),
                    double_sided: m.double_sided as u32,
                    emission_texture_offset,
                    emission_texture_width,
                    emission_texture_height,
                    pad0: 0,
                }
            })
            .collect();
        let materials = Buffer::with_data(gpu, "materials", storage, bytemuck::cast_slice(&materials))?;
        let texels = Buffer::with_data(gpu, "texels", storage, bytemuck::cast_slice(&texels))?;
        let neighbours = scene.coplanar_neighbours();
        let coplanar_neighbours =
            Buffer::with_data(gpu, "coplanar neighbours", storage, bytemuck::cast_slice(&neighbours))?;
        let emitter_table = EmitterTable::from_scene(scene);
        let emitters = Buffer::with_data(gpu, "emitters", storage, bytemuck::cast_slice(&emitter_table.emitters))?;
        let bvh = SceneBvh::build(gpu, scene)?;
        let addresses = SceneAddresses {
            positions: address_words(vertices.positions.device_address()),
            normals: address_words(vertices.normals.device_address()),
            uvs: address_words(vertices.uvs.device_address()),
            triangle_materials: address_words(triangle_materials.device_address()),
            materials: address_words(materials.device_address()),
            texels: address_words(texels.device_address()),
        };
        let addresses = Buffer::with_data(
            gpu,
            "scene addresses",
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            bytemuck::bytes_of(&addresses),
        )?;
        Ok(GpuScene {
            addresses,
            emitters,
            emitter_table,
            vertices,
            vertex_count: scene.vertices.len() as u32,
            triangle_materials,
            materials,
            texels,
            coplanar_neighbours,
            bvh,
            placed_version: 0,
        })
    }
}

impl GpuScene {
    pub fn import<'r>(&'r self, graph: &mut Graph<'r>) -> SceneHandles {
        SceneHandles {
            positions: graph.import_buffer(&self.vertices.positions),
            normals: graph.import_buffer(&self.vertices.normals),
            uvs: graph.import_buffer(&self.vertices.uvs),
            triangle_materials: graph.import_buffer(&self.triangle_materials),
            materials: graph.import_buffer(&self.materials),
            texels: graph.import_buffer(&self.texels),
            coplanar_neighbours: graph.import_buffer(&self.coplanar_neighbours),
            emitters: graph.import_buffer(&self.emitters),
            addresses: graph.import_buffer(&self.addresses),
        }
    }
}

/// The scene's buffers in one frame's graph.
pub struct SceneHandles {
    pub positions: BufferHandle,
    pub normals: BufferHandle,
    pub uvs: BufferHandle,
    pub triangle_materials: BufferHandle,
    pub materials: BufferHandle,
    pub texels: BufferHandle,
    /// Only the visible-disk pass binds it (visible_disk.rs): it is not part of scene.glsl.
    pub coplanar_neighbours: BufferHandle,
    /// Only the passes that light surfaces or emit photons bind it (`emitters.glsl`).
    pub emitters: BufferHandle,
    pub addresses: BufferHandle,
}

impl SceneHandles {
    /// Declares that `pass` reads the surfaces (`scene.glsl`) in `stage`.
    pub fn declare(&self, pass: &mut PassBuilder<'_, '_>, stage: Stage) -> SceneBindings {
        let resources = SceneResources {
            vertex_positions: &self.positions,
            vertex_normals: &self.normals,
            vertex_uvs: &self.uvs,
            triangle_materials: &self.triangle_materials,
            materials: &self.materials,
            texels: &self.texels,
            scene_addresses: &self.addresses,
        };
        SceneBindings::declare(pass, stage, resources)
    }

    /// Declares that `pass` reads the emissive triangles (`emitters.glsl`) in `stage`.
    pub fn declare_emitters(&self, pass: &mut PassBuilder<'_, '_>, stage: Stage) -> EmitterBindings {
        EmitterBindings::declare(pass, stage, EmitterResources { emitters: &self.emitters })
    }
}

/// A glTF light as the shaders use it: colour × intensity, cone cosines.
pub fn gpu_light(l: &leakless_scene::Light) -> Light {
    let (kind, cos_outer, cos_inner) = match l.kind {
        LightKind::Point => (gpu_types::LIGHT_POINT, -1.0, -1.0),
        LightKind::Spot { inner_cone, outer_cone } => (gpu_types::LIGHT_SPOT, outer_cone.cos(), inner_cone.cos()),
        LightKind::Directional => (gpu_types::LIGHT_DIRECTIONAL, 1.0, 1.0),
    };
    Light {
        position: l.position.to_array(),
        kind,
        direction: l.direction.normalize_or(Vec3::NEG_Z).to_array(),
        cos_outer,
        intensity: (l.color * l.intensity).to_array(),
        cos_inner,
    }
}
