//! Layered linear EXR: `R,G,B` final radiance and one `<layer>.R/G/B` channel group per
//! layer (the single-part layer convention tev, Nuke and Blender read), with header
//! attributes naming the scene, method and parameters.

use std::path::Path;

use exr::prelude::*;

use crate::error::{RenderError, Result};

/// One named image layer; the empty name is the final image (`R,G,B`).
pub struct ExrLayer<'a> {
    pub name: &'a str,
    pub pixels: &'a [[f32; 3]],
}

pub fn write(
    path: &Path,
    width: u32,
    height: u32,
    layers: &[ExrLayer<'_>],
    attributes: &[(&str, String)],
) -> Result<()> {
    let out_err = |message: String| RenderError::Output { path: path.display().to_string(), message };
    let size = (width as usize, height as usize);
    let mut channels = SmallVec::<[AnyChannel<FlatSamples>; 4]>::new();
    for layer in layers {
        if layer.pixels.len() != size.0 * size.1 {
            return Err(out_err(format!(
                "layer {:?} has {} pixels, expected {}",
                layer.name,
                layer.pixels.len(),
                size.0 * size.1
            )));
        }
        for (c, suffix) in ["R", "G", "B"].iter().enumerate() {
            let name = if layer.name.is_empty() { suffix.to_string() } else { format!("{}.{suffix}", layer.name) };
            let samples: Vec<f32> = layer.pixels.iter().map(|p| p[c]).collect();
            channels.push(AnyChannel::new(name.as_str(), FlatSamples::F32(samples)));
        }
    }
    let mut layer_attributes = LayerAttributes::default();
    for (key, value) in attributes {
        let text = |s: &str| {
            Text::new_or_none(s.chars().filter(|c| c.is_ascii() && !c.is_ascii_control()).collect::<String>())
        };
        let (Some(key), Some(value)) = (text(key), text(value)) else {
            return Err(out_err(format!("header attribute {key:?} is not representable")));
        };
        layer_attributes.other.insert(key, AttributeValue::Text(value));
    }
    let layer = Layer::new(size, layer_attributes, Encoding::SMALL_LOSSLESS, AnyChannels::sort(channels));
    Image::from_layer(layer).write().to_file(path).map_err(|e| out_err(e.to_string()))
}

/// Reads an EXR written by [`write`]: every channel by name, and the header text attributes.
pub struct ReadExr {
    pub width: u32,
    pub height: u32,
    pub channels: Vec<(String, Vec<f32>)>,
    pub attributes: Vec<(String, String)>,
}

impl ReadExr {
    pub fn channel(&self, name: &str) -> Option<&[f32]> {
        self.channels.iter().find(|(n, _)| n == name).map(|(_, v)| v.as_slice())
    }
    pub fn attribute(&self, name: &str) -> Option<&str> {
        self.attributes.iter().find(|(n, _)| n == name).map(|(_, v)| v.as_str())
    }
}

pub fn read(path: &Path) -> Result<ReadExr> {
    let image = read_all_flat_layers_from_file(path)
        .map_err(|e| RenderError::Output { path: path.display().to_string(), message: e.to_string() })?;
    let layer = image
        .layer_data
        .first()
        .ok_or_else(|| RenderError::Output { path: path.display().to_string(), message: "no layer".into() })?;
    let channels =
        layer.channel_data.list.iter().map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect())).collect();
    let mut attributes: Vec<(String, String)> = Vec::new();
    for (k, v) in layer.attributes.other.iter().chain(image.attributes.other.iter()) {
        if let AttributeValue::Text(t) = v {
            attributes.push((k.to_string(), t.to_string()));
        }
    }
    Ok(ReadExr { width: layer.size.0 as u32, height: layer.size.1 as u32, channels, attributes })
}
