//! What the project's scenes say about themselves in their glTF `extras` (written by
//! `tools/gen-scenes`, described in docs/scenes.md): here, the box of the room that must stay
//! dark, which the stress tests and `leakless stability` measure.

use leakless_scene::Scene;

/// The scene's `extras` as JSON (null when it has none).
pub fn extras(scene: &Scene) -> serde_json::Value {
    scene.extras.as_deref().and_then(|e| serde_json::from_str(e).ok()).unwrap_or_default()
}

/// The scene's dark box (extras `dark_min`, `dark_max`), or `None` for a scene without one.
pub fn dark_box(scene: &Scene) -> Option<([f32; 3], [f32; 3])> {
    let e = extras(scene);
    let v = |k: &str| -> Option<[f32; 3]> {
        let a = e[k].as_array()?;
        Some([a.first()?.as_f64()? as f32, a.get(1)?.as_f64()? as f32, a.get(2)?.as_f64()? as f32])
    };
    Some((v("dark_min")?, v("dark_max")?))
}

/// The pixels whose surface (G-buffer `position`, w > 0 where a surface was hit) lies in the
/// scene's dark box (extras `dark_min`, `dark_max`), or `None` for a scene without one.
pub fn in_dark_box(scene: &Scene, positions: &[[f32; 4]]) -> Option<Vec<bool>> {
    let (lo, hi) = dark_box(scene)?;
    Some(positions.iter().map(|p| p[3] > 0.0 && (0..3).all(|i| p[i] >= lo[i] && p[i] <= hi[i])).collect())
}
