//! Visibility accelerations (`--visibility exact`): what lux adds to plain shadow rays to answer
//! "what does a point see of a light" sooner — closed forms where nothing can block a light,
//! exact penumbrae behind a few triangles, patches of surface that share those answers, a
//! shadow BVH of flat cards' outlines, and per-tile short lists of what camera rays can meet.

pub(crate) mod cone;
pub(crate) mod frustum;
pub(crate) mod patches;
pub(crate) mod penumbra;
pub(crate) mod planar;
pub(crate) mod pyramid;
pub(crate) mod regions;
pub(crate) mod shadows;

pub use cone::{ConeSearch, INSTANCED, RayEnds, ShadowCone};
pub use frustum::RayFrustum;
pub use patches::ClearPatches;
pub use pyramid::ShadowPyramid;
pub use shadows::{FewTriangles, ShadowBvh, Shadows};

/// The least and most ray-origin offset (`geometry::offset_scale`) over the points within
/// `spread` of `q` (a patch of [`ShadowCone::patch`] or [`ShadowPyramid::patch`]); `None` for a
/// negative or non-finite spread.
pub(crate) fn patch_offsets(q: glam::DVec3, spread: f64) -> Option<[f64; 2]> {
    if !(spread >= 0.0 && spread.is_finite()) {
        return None;
    }
    let m = q.abs().max_element();
    Some([
        crate::geometry::offset_scale(glam::DVec3::splat((m - spread).max(0.0))),
        crate::geometry::offset_scale(glam::DVec3::splat(m + spread)),
    ])
}

/// A scene's geometry with its shadow BVH, for tests: the shadow queries of [`Shadows`] and,
/// through `Deref`, the geometry's own.
#[cfg(test)]
pub(crate) struct TestShadows {
    g: crate::geometry::Geometry,
    bvh: ShadowBvh,
}

#[cfg(test)]
impl TestShadows {
    /// The geometry of `scene` and its shadow BVH.
    pub fn new(scene: &lux_usd::Scene) -> TestShadows {
        let g = crate::geometry::Geometry::new(scene);
        let bvh = ShadowBvh::new(scene, &g);
        TestShadows { g, bvh }
    }

    /// The shadow queries.
    pub fn shadows(&self) -> Shadows<'_> {
        self.bvh.view(&self.g)
    }

    pub fn cone_clear(
        &self,
        cone: &impl crate::geometry::Region,
        casts: &impl Fn(usize) -> bool,
    ) -> bool {
        self.shadows().cone_clear(cone, casts)
    }

    pub fn occluded(&self, o: glam::DVec3, d: glam::DVec3, tmin: f64, tmax: f64) -> bool {
        self.shadows().occluded(o, d, tmin, tmax)
    }

    pub fn occluded_among(
        &self,
        few: &FewTriangles,
        o: glam::DVec3,
        d: glam::DVec3,
        tmin: f64,
        tmax: f64,
    ) -> bool {
        self.shadows().occluded_among(few, o, d, tmin, tmax)
    }

    pub fn triangles_in(&self, frustum: &RayFrustum, cap: usize) -> Option<Box<[u32]>> {
        self.shadows().triangles_in(frustum, cap)
    }

    pub fn intersect_among(
        &self,
        scene: &lux_usd::Scene,
        ids: &[u32],
        o: glam::DVec3,
        d: glam::DVec3,
        tmin: f64,
        tmax: f64,
    ) -> Option<crate::geometry::Hit> {
        self.shadows().intersect_among(scene, ids, o, d, tmin, tmax)
    }
}

#[cfg(test)]
impl std::ops::Deref for TestShadows {
    type Target = crate::geometry::Geometry;
    fn deref(&self) -> &crate::geometry::Geometry {
        &self.g
    }
}
