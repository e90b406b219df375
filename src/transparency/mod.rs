//! CPU models of the eye transparency techniques: the specification every technique's GPU output must equal,
//! as `crate::visibility` is for the shadow methods.

pub mod exact;
pub mod wboit;

/// One eye fragment of a pixel, as the GPU's per-pixel lists record it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EyeFragment {
    /// Distance from the eye in units of the camera-to-target distance (>= 0; what `store_hair` receives).
    pub depth: f32,
    /// Segment id (index of the segment's first point); ties in depth are ordered by it.
    pub segment: u32,
    /// Shaded linear radiance, not premultiplied.
    pub color: [f32; 3],
    /// Coverage in [0, 1].
    pub alpha: f32,
}

/// What every model may need beyond the pixel's own fragments.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelContext {
    /// The scene's global hair alpha (occupancy ordering assumes one alpha, S&A §3.4).
    pub hair_alpha: f32,
    /// [near, far] of every fragment depth in the frame (the hair's fitted eye range, same units as depth).
    pub depth_range: [f32; 2],
}

/// A technique's CPU model: the linear colour of one pixel from its fragments (in any order) over `background`.
pub trait Compositor: Send + Sync {
    fn composite(&self, fragments: &[EyeFragment], background: [f32; 3]) -> [f32; 3];
}

/// The fragments front to back on the total key (depth bits, segment) (ties kept).
pub fn front_to_back(fragments: &[EyeFragment]) -> Vec<EyeFragment> {
    let mut v = fragments.to_vec();
    v.sort_by_key(|f| (f.depth.to_bits(), f.segment));
    v
}
