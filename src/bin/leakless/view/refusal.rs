//! A change the device cannot render, or that the settings refuse, is not made. The app keeps
//! what it shows and says why in the panel and on stderr, where `render` would exit. Examples:
//! `=` doubling the paths past the photon buffer, or a window too large for the view samples'
//! workgroups. A window too large for the device at the asked render scale renders at a
//! smaller scale.

use leakless::RenderError;

/// The outcome of a change of settings: `None` if made, else why not (a device limit or an
/// invalid setting). Any other error ends the app.
pub(super) fn refused(result: leakless::Result<()>) -> anyhow::Result<Option<String>> {
    match result {
        Ok(()) => Ok(None),
        Err(e @ (RenderError::Limit(_) | RenderError::Settings(_))) => Ok(Some(e.to_string())),
        Err(e) => Err(e.into()),
    }
}

/// Each step down of the render scale when a window's render size does not fit the device.
const SCALE_STEP: f32 = 0.8;

/// The render size for a `window` at `scale` rendered pixels per window pixel. `set_size`
/// tries each size; while it refuses, the scale steps down by `SCALE_STEP`. Returns the size
/// set, and why the first size tried was refused, if it was.
pub(super) fn fit_render_size(
    window: (u32, u32),
    scale: f32,
    mut set_size: impl FnMut(u32, u32) -> leakless::Result<()>,
) -> anyhow::Result<((u32, u32), Option<String>)> {
    let scaled = |v: u32, s: f32| ((v as f32 * s).round() as u32).max(1);
    let mut s = scale;
    let mut first_refusal = None;
    loop {
        let size = (scaled(window.0, s), scaled(window.1, s));
        match refused(set_size(size.0, size.1))? {
            None => return Ok((size, first_refusal)),
            // Not even one pixel renders: nothing smaller would.
            Some(why) if size == (1, 1) => anyhow::bail!(why),
            Some(why) => {
                first_refusal.get_or_insert(why);
                s *= SCALE_STEP;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn limit(what: &str) -> leakless::Result<()> {
        Err(RenderError::Limit(what.into()))
    }

    #[test]
    fn a_window_past_the_limit_renders_at_the_largest_scale_that_fits() {
        // A device that renders at most 100,000 pixels.
        let fits = |w: u32, h: u32| if w * h <= 100_000 { Ok(()) } else { limit("too many view samples") };
        let mut tried = Vec::new();
        let (size, why) = fit_render_size((1000, 500), 1.0, |w, h| {
            tried.push((w, h));
            fits(w, h)
        })
        .unwrap();
        assert_eq!(why.as_deref(), Some("too many view samples"));
        // 1000×500, 800×400, 640×320, 512×256, 410×205 (84,050 pixels).
        assert_eq!(tried, [(1000, 500), (800, 400), (640, 320), (512, 256), (410, 205)]);
        assert_eq!(size, (410, 205));
        // A size that fits is kept, with nothing to say.
        assert_eq!(fit_render_size((300, 200), 1.0, fits).unwrap(), ((300, 200), None));
    }

    #[test]
    fn only_limits_and_settings_are_refusals() {
        assert_eq!(refused(limit("x")).unwrap().as_deref(), Some("x"));
        assert!(refused(Err(RenderError::Settings("y".into()))).unwrap().unwrap().contains('y'));
        let other = Err(RenderError::Output { path: "p".into(), message: "m".into() });
        assert!(refused(other).is_err(), "an error that is not a refusal ends the app");
        // Where even one pixel is refused, the app ends with the reason.
        assert!(fit_render_size((10, 10), 1.0, |_, _| limit("never")).is_err());
    }
}
