//! Ray/box and watertight ray/triangle tests, operation for operation as in
//! `shaders-glsl/trace_compute.glsl` (`bvh_box_entry`, `bvh_triangle`).

/// Ize's factor for the far slab distance, 1 + 2γ₃ with γ₃ = 3ε/(1-3ε), ε = 2⁻²⁴ ("Robust BVH
/// Ray Traversal", JCGT 2013): with it the slab test never culls a box the exact ray touches.
pub(crate) const ROBUST_FAR: f32 = 1.000_000_4;

/// A ray prepared for traversal: what the box test and the watertight triangle test need,
/// computed once per ray.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    pub origin: [f32; 3],
    /// 1/dir per axis; ±inf on an axis the ray does not move along.
    inv_dir: [f32; 3],
    /// The axis along which |dir| is largest (the shear's z), then the other two in cyclic order.
    k: [usize; 3],
    /// Shear constants: dir[kx]/dir[kz], dir[ky]/dir[kz], 1/dir[kz].
    shear: [f32; 3],
}

impl Ray {
    pub fn new(origin: [f32; 3], dir: [f32; 3]) -> Self {
        let abs = dir.map(f32::abs);
        // Ties pick the lowest axis, as in the shader.
        let kz = if abs[0] >= abs[1] && abs[0] >= abs[2] {
            0
        } else if abs[1] >= abs[2] {
            1
        } else {
            2
        };
        // Woop et al. swap kx and ky when dir[kz] < 0 to keep the winding; every surface is
        // two-sided here and the swap flips the signs of U, V, W and det together, which
        // changes neither the decision nor t nor the barycentrics, so it is left out.
        let kx = (kz + 1) % 3;
        let ky = (kx + 1) % 3;
        Self {
            origin,
            inv_dir: dir.map(|d| 1.0 / d),
            k: [kx, ky, kz],
            shear: [dir[kx] / dir[kz], dir[ky] / dir[kz], 1.0 / dir[kz]],
        }
    }

    /// Where the ray enters the box `lo`..`hi` within [`tmin`, `tmax`], or `None` if it misses.
    ///
    /// The near and far planes are chosen by the sign of 1/dir rather than with min/max, so an
    /// axis the ray does not move along (1/dir = ±inf) gives ±inf, or NaN exactly on a face
    /// plane; the comparisons are written so that NaN leaves the interval unchanged, which is
    /// what a ray lying in a face plane needs (Williams et al. 2005; pbrt).
    pub(crate) fn box_entry(&self, lo: [f32; 3], hi: [f32; 3], tmin: f32, tmax: f32) -> Option<f32> {
        let mut near = tmin;
        let mut far = tmax;
        for a in 0..3 {
            let (near_plane, far_plane) = if self.inv_dir[a] < 0.0 { (hi[a], lo[a]) } else { (lo[a], hi[a]) };
            let t_near = (near_plane - self.origin[a]) * self.inv_dir[a];
            let t_far = (far_plane - self.origin[a]) * self.inv_dir[a] * ROBUST_FAR;
            if t_near > near {
                near = t_near;
            }
            if t_far < far {
                far = t_far;
            }
        }
        (near <= far).then_some(near)
    }
}

/// The watertight ray/triangle test of Woop, Benthin and Wald ("Watertight Ray/Triangle
/// Intersection", JCGT 2013): translate to the ray origin, permute so the ray's dominant axis
/// is z, shear so the ray becomes the +z axis, and evaluate the three 2D edge functions at the
/// origin. Returns `(t, [u, v])` for a hit with `t` in (`tmin`, `tmax`), where
/// p = (1-u-v)·v0 + u·v1 + v·v2.
///
/// Watertight without the paper's double-precision fallback: a vertex shared by two triangles
/// is transformed by the same operations to the same values, and the edge function of a
/// shared edge evaluated from the other side is `x_i·y_j - y_i·x_j` with the operands swapped,
/// exactly the negation. So a ray through a shared edge sees 0 (or ±the same value) from both
/// triangles, and since an edge function of exactly 0 counts as inside, at least one of them
/// reports the hit. The shader marks these computations `precise` so no fused multiply-add
/// breaks that symmetry.
#[inline]
pub fn intersect_triangle(
    ray: &Ray,
    v0: [f32; 3],
    v1: [f32; 3],
    v2: [f32; 3],
    tmin: f32,
    tmax: f32,
) -> Option<(f32, [f32; 2])> {
    let [kx, ky, kz] = ray.k;
    let [sx, sy, sz] = ray.shear;
    let o = ray.origin;
    let rel = |v: [f32; 3]| [v[0] - o[0], v[1] - o[1], v[2] - o[2]];
    let (a, b, c) = (rel(v0), rel(v1), rel(v2));
    let ax = a[kx] - sx * a[kz];
    let ay = a[ky] - sy * a[kz];
    let bx = b[kx] - sx * b[kz];
    let by = b[ky] - sy * b[kz];
    let cx = c[kx] - sx * c[kz];
    let cy = c[ky] - sy * c[kz];
    // Twice the signed areas of the sub-triangles the ray splits the projected triangle into.
    let u = cx * by - cy * bx;
    let v = ax * cy - ay * cx;
    let w = bx * ay - by * ax;
    // Mixed signs: the ray passes outside. Zeros count as inside, consistently for both
    // triangles of a shared edge.
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 {
        return None; // degenerate, or the ray lies in the triangle's plane
    }
    let t_scaled = u * (sz * a[kz]) + v * (sz * b[kz]) + w * (sz * c[kz]);
    let inv_det = 1.0 / det;
    let t = t_scaled * inv_det;
    // Written so NaN (from NaN or infinite input) rejects.
    if !(t > tmin && t < tmax) {
        return None;
    }
    Some((t, [v * inv_det, w * inv_det]))
}
