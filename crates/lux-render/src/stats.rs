//! What a render counts: per worker while it renders ([`Counters`]), and for the whole render
//! ([`RenderStats`]). Plain numbers: this module imports nothing of the renderer.

/// Counters of a finished render.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Pixels rendered.
    pub pixels: u64,
    /// Camera samples traced (pixels × spp, plus the adaptive extra samples; a light tracer's
    /// band traces the whole frame's).
    pub samples: u64,
    /// Adaptive extra samples among them (`crate::adaptive`).
    pub adaptive_samples: u64,
    /// Rays traced through the BVH: camera, shadow and BSDF rays.
    pub rays: u64,
    /// Shadow rays among them.
    pub shadow_rays: u64,
    /// Light samples drawn.
    pub light_samples: u64,
    /// Camera samples whose radiance came out NaN or infinite and were counted as black. Any
    /// non-zero count is a renderer or input defect: the luxtest and robustness tests require 0.
    pub non_finite_samples: u64,
    /// Wall-clock seconds of the render loop (scene preparation excluded).
    pub seconds: f64,
}

/// What one worker counts while it renders (summed into [`RenderStats`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Rays traced.
    pub rays: u64,
    /// Shadow rays among them.
    pub shadow: u64,
    /// Light samples drawn.
    pub light_samples: u64,
    /// Non-finite camera samples.
    pub non_finite: u64,
    /// Shadow rays that found an occluder (what the penumbra pass looks at).
    pub blocked: u64,
}
