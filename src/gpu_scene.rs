//! The scene as the GPU sees it: vertex, material, texel and light buffers, uploaded once.

use ash::vk;
use glam::Vec3;
use leakless_device::{Buffer, Gpu};
use leakless_scene::{LightKind, Scene};

use crate::error::Result;
use crate::gpu_types::{self, Light, Material};

pub struct GpuScene {
    /// `Vertex` × 3 per triangle, world space.
    pub vertices: Buffer,
    pub vertex_count: u32,
    /// One material index per triangle.
    pub triangle_materials: Buffer,
    pub materials: Buffer,
    /// Every texture's texels, RGBA8 packed in one word each.
    pub texels: Buffer,
    pub lights: Buffer,
    pub light_count: u32,
}

impl GpuScene {
    pub fn upload(gpu: &Gpu, scene: &Scene) -> Result<GpuScene> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let vertices = Buffer::with_data(
            gpu,
            "vertices",
            vk::BufferUsageFlags::VERTEX_BUFFER | storage,
            bytemuck::cast_slice(&scene.vertices),
        )?;
        let triangle_materials = Buffer::with_data(
            gpu,
            "triangle materials",
            storage,
            bytemuck::cast_slice(&scene.triangle_material),
        )?;

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
                let texture = m
                    .texture
                    .map(|i| (texture_offsets[i as usize], &scene.textures[i as usize]));
                Material {
                    base_color: m.base_color.to_array(),
                    texture_offset: texture.map_or(0, |(o, _)| o),
                    texture_width: texture.map_or(0, |(_, t)| t.width),
                    texture_height: texture.map_or(0, |(_, t)| t.height),
                    alpha_cutoff: m.alpha_cutoff.unwrap_or(-1.0),
                }
            })
            .collect();
        let materials =
            Buffer::with_data(gpu, "materials", storage, bytemuck::cast_slice(&materials))?;
        let texels = Buffer::with_data(gpu, "texels", storage, bytemuck::cast_slice(&texels))?;

        let lights: Vec<Light> = scene.lights.iter().map(gpu_light).collect();
        let lights_buffer =
            Buffer::with_data(gpu, "lights", storage, bytemuck::cast_slice(&lights))?;
        Ok(GpuScene {
            vertices,
            vertex_count: scene.vertices.len() as u32,
            triangle_materials,
            materials,
            texels,
            lights: lights_buffer,
            light_count: lights.len() as u32,
        })
    }
}

/// A glTF light as the shaders use it: colour × intensity, cone cosines.
pub fn gpu_light(l: &leakless_scene::Light) -> Light {
    let (kind, cos_outer, cos_inner) = match l.kind {
        LightKind::Point => (gpu_types::LIGHT_POINT, -1.0, -1.0),
        LightKind::Spot {
            inner_cone,
            outer_cone,
        } => (gpu_types::LIGHT_SPOT, outer_cone.cos(), inner_cone.cos()),
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
