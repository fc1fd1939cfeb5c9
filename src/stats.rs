//! Engine statistics read back from graph resources after a render.

use crate::gpu::readback::ImageF32;

/// The reflections pass's per-pixel record: 1 reused from screen space,
/// 0 traced and shaded, 0.5 no ray traced (a rough lobe's Russian
/// roulette), -1 not specular.
pub const REFLECT_REUSE: &str = "reflect_reuse";

/// Reflection rays served from screen space, of the rays traced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReuseShare {
    /// Pixels served from screen space.
    pub reused: usize,
    /// Pixels whose reflection ray was traced (reused or shaded).
    pub traced: usize,
    /// Specular pixels.
    pub specular: usize,
}

impl ReuseShare {
    /// Counts the pixels of a `reflect_reuse` image (its red channel).
    pub fn of(img: &ImageF32) -> ReuseShare {
        let specular = img.data.iter().filter(|p| p[0] >= 0.0).count();
        let reused = img.data.iter().filter(|p| p[0] == 1.0).count();
        let traced = img.data.iter().filter(|p| p[0] == 1.0 || p[0] == 0.0).count();
        ReuseShare { reused, traced, specular }
    }

    /// The share of traced rays reused, in [0, 1]; 0 without any.
    pub fn share(&self) -> f64 {
        if self.traced == 0 { 0.0 } else { self.reused as f64 / self.traced as f64 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn share_counts_only_traced_rays() {
        let mut img = ImageF32::new(5, 1);
        for (p, v) in img.data.iter_mut().zip([-1.0, 0.0, 1.0, 1.0, 0.5]) {
            p[0] = v;
        }
        let s = ReuseShare::of(&img);
        assert_eq!((s.reused, s.traced, s.specular), (2, 3, 4));
        assert!((s.share() - 2.0 / 3.0).abs() < 1e-12);
        assert_eq!(ReuseShare::of(&ImageF32::new(2, 2)).share(), 0.0);
    }
}
