//! Visibility: what a point sees of a light, and what a tile's camera rays can meet.
//!
//! [`Visibility::Rays`] is the plain renderer: every light sample traced as a shadow ray
//! through the scene's BVH, every camera ray through the BVH. [`Visibility::Exact`] adds
//! accelerations that change the cost and, where they answer in closed form, remove noise —
//! never the expected image:
//!
//! - **closed forms** where nothing can block a rect, disk or sphere light of uniform radiance
//!   from a Lambertian point (a conservative search of the shadow rays' region: a cone
//!   `cone.rs`, a pyramid `pyramid.rs`, `regions.rs`), whose light-only estimate is then its
//!   exact unshadowed irradiance `L·Π` (lux-irradiance);
//! - **exact penumbrae** behind a few blockers (`penumbra.rs`): `L·(Π − Σ H)`, of closed
//!   convex meshes only the faces towards the point (`solid.rs`);
//! - **patches** of surface that share those searches (`patches.rs`, per worker);
//! - a **shadow BVH** where flat cards tiling a convex polygon stand as their outlines
//!   (`planar.rs`, `shadows.rs`), whose outlines the penumbrae use;
//! - per-tile **short lists** of the triangles camera rays can meet, and **empty tiles** whose
//!   rays meet nothing (`frustum.rs`).
//!
//! The rest of the renderer asks through a few questions and nothing else:
//! [`Visibility::occluded`] and [`Visibility::first_occluder_at`] (shadow rays),
//! [`Visibility::tile`] (what a tile's camera rays can meet, asked by the tile loop: nothing
//! known for rays), [`Visibility::camera_hit`] (a camera ray's hit as the tile knows it) and
//! [`Visibility::estimate`] (a light's light-only estimate at a point: exact, or sample it
//! with a [`ShadowHint`] — always sample for rays). No type of this folder's is known outside
//! it but those questions' answers ([`Scratch`], [`Tile`], [`CameraHit`], [`Estimate`],
//! [`ShadowHint`]).
//!
//! Adding an acceleration: a file here, its use inside these methods (and its state in
//! [`Scratch`] or [`Visibility::Exact`]); an integrator sees it only through their answers.

pub(crate) mod cone;
pub(crate) mod frustum;
pub(crate) mod patches;
pub(crate) mod penumbra;
pub(crate) mod planar;
pub(crate) mod pyramid;
pub(crate) mod regions;
pub(crate) mod shadows;
pub(crate) mod solid;

use crate::camera::Camera;
use crate::geometry::{Geometry, Hit, Occluder, Region};
use crate::light::{Light, LightBase, LightFrom};
use crate::material::SurfacePoint;
use crate::world::World;
pub(crate) use cone::{ConeSearch, RayEnds, ShadowCone};
pub(crate) use frustum::RayFrustum;
use glam::DVec3;
use lux_usd::Scene;
pub(crate) use patches::ClearPatches;
pub(crate) use pyramid::ShadowPyramid;
pub(crate) use shadows::ShadowBvh;
pub(crate) use shadows::{FewTriangles, Shadows};

/// `RenderOptions::visibility` / `--visibility`: how what a point sees of a light is found.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum VisibilityMode {
    /// Shadow rays through the scene's BVH for every light sample, camera rays through the
    /// BVH: the plain renderer, which the exact answers are tested against.
    Rays,
    /// Closed forms, exact penumbrae, patches, the card BVH, tile lists and empty tiles where
    /// they apply (the default).
    #[default]
    Exact,
}

/// Most triangles a tile's camera rays test as a list ([`Visibility::tile`]): beyond that the
/// BVH's traversal costs less.
pub const TILE_TRIANGLES: usize = 12;

/// How a render finds what a point sees of a light ([`VisibilityMode`]), prepared for a scene.
pub enum Visibility {
    /// Shadow rays and camera rays through the scene's BVH.
    Rays,
    /// The accelerations of this folder, with the shadow BVH of card outlines.
    Exact(Box<ShadowBvh>),
}

/// What one worker carries for the visibility from sample to sample: the patches of surface it
/// has searched (kept from tile to tile: each answer is a function of its key alone) and what
/// the current tile's camera rays can meet.
#[derive(Clone, Debug, Default)]
pub struct Scratch {
    /// Patch answers (`patches.rs`).
    patches: ClearPatches,
    /// Room for the exact penumbrae's polygons (`penumbra.rs`).
    penumbra: penumbra::Room,
    /// The current tile ([`Visibility::tile`]; the default knows nothing).
    pub tile: Tile,
}

/// What the camera rays through one tile of pixels can meet ([`Visibility::tile`]); the
/// default knows nothing (every ray through the BVH).
#[derive(Clone, Debug, Default)]
pub struct Tile {
    /// The world triangles the rays can hit, when few; `None`: they take the BVH.
    triangles: Option<Box<[u32]>>,
    /// Nothing at all: no triangle, no camera-visible analytic light and no background, so
    /// every ray ends black with alpha 0.
    empty: bool,
}

impl Tile {
    /// Whether every camera ray of the tile meets nothing ([`CameraHit::Empty`]).
    pub fn is_empty(&self) -> bool {
        self.empty
    }

    /// How many triangles its rays test as a list, when they do (`None`: the BVH).
    pub fn listed(&self) -> Option<usize> {
        self.triangles.as_ref().map(|t| t.len())
    }
}

/// A camera ray's first surface as the tile knows it ([`Visibility::camera_hit`]).
#[derive(Clone, Copy, Debug)]
pub enum CameraHit {
    /// The tile holds nothing a camera ray can meet: black, alpha 0, no light, no background.
    Empty,
    /// The tile's short list answered: this hit, or none (lights and background still count).
    Known(Option<Hit>),
    /// Unknown: trace the ray through the BVH.
    Trace,
}

/// What the visibility knows of a shadow ray of a light sample ([`Visibility::estimate`]):
/// with the exact visibility, the few triangles that alone can stop it.
#[derive(Clone, Copy, Debug, Default)]
pub struct ShadowHint(Option<FewTriangles>);

impl ShadowHint {
    /// Nothing known: the BVH.
    pub const NONE: ShadowHint = ShadowHint(None);
}

/// A light's light-only estimate at a point ([`Visibility::estimate`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct Estimate {
    /// Exact: the direction to evaluate the (Lambertian) BSDF in and the fraction of the
    /// light's closed form `L·Π` (`LightFrom::unshadowed`) that reaches the point.
    pub exact: Option<(DVec3, f64)>,
    /// Otherwise the light is sampled, its shadow rays with this hint.
    pub hint: ShadowHint,
}

/// The empty shadow BVH of [`Visibility::Rays`]: its shadow rays use the world BVH.
static NO_SHADOW_BVH: ShadowBvh = ShadowBvh::NONE;

impl Visibility {
    /// The visibility of `mode` for `scene`'s geometry `g`.
    pub fn new(mode: VisibilityMode, scene: &Scene, g: &Geometry) -> Visibility {
        match mode {
            VisibilityMode::Rays => Visibility::Rays,
            VisibilityMode::Exact => Visibility::Exact(Box::new(ShadowBvh::new(scene, g))),
        }
    }

    /// Shadow rays over `g`: through the world BVH, or the exact visibility's BVH of card
    /// outlines (the same surfaces).
    #[inline]
    pub(crate) fn shadows<'a>(&'a self, g: &'a Geometry) -> Shadows<'a> {
        match self {
            Visibility::Rays => NO_SHADOW_BVH.view(g),
            Visibility::Exact(b) => b.view(g),
        }
    }

    /// Whether a triangle of `g` stops the shadow ray `origin + t·dir`, `t ∈ (0, tmax)`, with
    /// what the visibility knows of it (`hint`: the few triangles that alone can, else the
    /// BVH).
    #[inline]
    pub fn occluded(
        &self,
        g: &Geometry,
        hint: &ShadowHint,
        origin: DVec3,
        dir: DVec3,
        tmax: f64,
    ) -> bool {
        let shadows = self.shadows(g);
        match &hint.0 {
            Some(few) => shadows.occluded_among(few, origin, dir, 0.0, tmax),
            None => shadows.occluded(origin, dir, 0.0, tmax),
        }
    }

    /// Distance to the first triangle of `g` on the shadow ray `origin + t·dir`,
    /// `t ∈ (tmin, tmax)` (`Geometry::first_occluder`).
    #[inline]
    pub fn first_occluder(
        &self,
        g: &Geometry,
        origin: DVec3,
        dir: DVec3,
        tmin: f64,
        tmax: f64,
    ) -> Option<f64> {
        self.shadows(g).first_occluder(origin, dir, tmin, tmax)
    }

    /// The first triangle of `g` on the shadow ray and what it belongs to
    /// (`Geometry::first_occluder_at`, for shadow linking).
    #[inline]
    pub fn first_occluder_at(
        &self,
        g: &Geometry,
        origin: DVec3,
        dir: DVec3,
        tmin: f64,
        tmax: f64,
    ) -> Option<Occluder> {
        self.shadows(g).first_occluder_at(origin, dir, tmin, tmax)
    }

    /// What the camera rays through pixels `rect` of `camera` can meet: nothing known for
    /// rays; with the exact visibility, from the tile's frustum (`frustum.rs`), the world triangles in
    /// it (`None`, the BVH, with more than [`TILE_TRIANGLES`], with instances or partly
    /// transparent surfaces, whose rays go on past a hit), and whether it holds nothing at all
    /// — no triangle, no camera-visible light at infinity, and no camera-visible analytic light
    /// whose box reaches the frustum.
    pub fn tile(&self, w: &World, camera: &Camera, rect: [u32; 4]) -> Tile {
        let Visibility::Exact(_) = self else {
            return Tile::default();
        };
        let Some((lo, hi)) = w.geometry.world_bounds().filter(|_| !w.transparent) else {
            return Tile::default();
        };
        let Some(frustum) = RayFrustum::of_tile(camera, rect, lo.abs().max(hi.abs()).max_element())
        else {
            return Tile::default();
        };
        let shadows = self.shadows(w.geometry);
        let triangles = shadows.triangles_in(&frustum, TILE_TRIANGLES);
        let lights = &w.lights.lights;
        let empty = triangles.as_ref().is_some_and(|t| t.is_empty())
            && w.lights.background.is_empty()
            && w.lights.shapes.none_in(
                lights,
                |lo, hi| frustum.misses_box(lo, hi),
                |l| l.base().camera_visible,
            );
        Tile { triangles, empty }
    }

    /// A camera ray's first surface as the current `tile` knows it: nothing at all in an
    /// empty tile, the closest of its short list, else unknown.
    #[inline]
    pub fn camera_hit(
        &self,
        w: &World,
        tile: &Tile,
        (o, d, tmin, tmax): (DVec3, DVec3, f64, f64),
    ) -> CameraHit {
        if tile.empty {
            return CameraHit::Empty;
        }
        match &tile.triangles {
            Some(ids) => CameraHit::Known(
                self.shadows(w.geometry)
                    .intersect_among(w.scene, ids, o, d, tmin, tmax),
            ),
            None => CameraHit::Trace,
        }
    }

    /// The light-only estimate of light `li` (`light`, seen from the point as `from`) at the
    /// Lambertian point `sp`, when it is estimated by light sampling alone (`alone`): exact
    /// where nothing can block it — its closed form — or where a few triangles can — its exact
    /// penumbra —, else to be sampled, with the few triangles its shadow rays can meet when
    /// known. Always "sample" for rays.
    ///
    /// What can block the light is searched once for the point's patch of surface
    /// (`patches.rs`), then for the point unless the patch's blocker blocks its region too
    /// (without shadows, nothing blocks; with shadow linking, only what it keeps).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub fn estimate(
        &self,
        w: &World,
        scratch: &mut Scratch,
        sp: &SurfacePoint,
        li: usize,
        light: &Light,
        from: &LightFrom,
        alone: bool,
    ) -> Estimate {
        let Visibility::Exact(_) = self else {
            return Estimate::default();
        };
        let shadows = self.shadows(w.geometry);
        let base = light.base();
        let casts = |m| base.casts_shadow(m, None);
        let (patch, few) = match regions::shadow_ball(from) {
            Some(ball) if alone && base.shadow.enable => {
                let corners = regions::shadow_corners(from);
                let corners = corners.as_ref();
                scratch
                    .patches
                    .search(w.scene, &shadows, sp, li, ball, corners, &casts)
            }
            _ => (ConeSearch::Unsearched, None),
        };
        // With the patch's few possible blockers (opaque black shadows; those the light's
        // shadow links keep), the part of a sphere, rect or disk they leave visible, in closed
        // form (`penumbra.rs`).
        let mut exact = || {
            few.as_ref()
                .filter(|_| !w.transparent && base.black_shadows())
                .and_then(|few| penumbra::visible(&shadows, from, sp, few, &mut scratch.penumbra))
        };
        // The direction the closed form's BSDF is evaluated in (the ball's centre: a
        // Lambertian f is the same in every direction), and the fraction of the closed form
        // that passes.
        let unblocked = match patch {
            _ if !alone => None,
            // (the patch's region holds the point's: the light is above its horizon)
            ConeSearch::Clear => {
                regions::shadow_ball(from).map(|(centre, ..)| ((centre - sp.p).normalize(), 1.0))
            }
            // Something may block the patch, and the light's samples are its closed form where
            // unblocked: the exact penumbra, else the samples (a search of the point's own
            // region would only spare their shadow rays, at about their cost, and most often,
            // in a penumbra, find a blocker).
            ConeSearch::Blocked(_) if from.samples_exactly() => exact(),
            // The exact penumbra (a blocked patch's few blockers), else a rect's or disk's
            // pyramid (tighter than its ball's cone), else the cone.
            _ => exact().or_else(
                || match regions::shadow_pyramid(from, sp.p, sp.ng, sp.offset) {
                    Some(pyramid) => clear_from(&shadows, base, &pyramid, patch, &casts)
                        .then(|| (pyramid.axis(), 1.0)),
                    None => regions::shadow_cone(from, sp.p, sp.ng, sp.offset)
                        .filter(|cone| clear_from(&shadows, base, cone, patch, &casts))
                        .map(|cone| (cone.axis(), 1.0)),
                },
            ),
        };
        Estimate {
            exact: unblocked,
            hint: ShadowHint(few),
        }
    }
}

/// Whether no triangle can block the light's shadow rays inside `region`, from a point of a
/// patch whose search found `patch` (`patches.rs`): without shadows nothing can; a triangle of
/// the patch's that `region` does not rule out may; otherwise the point's own search of the
/// BVH (only the meshes its shadow linking keeps, `casts`) decides.
fn clear_from(
    shadows: &Shadows,
    base: &LightBase,
    region: &impl Region,
    patch: ConeSearch,
    casts: &impl Fn(usize) -> bool,
) -> bool {
    !base.shadow.enable
        || match patch {
            ConeSearch::Blocked(id) if !shadows.culls(region, id) => false,
            _ => shadows.cone_clear(region, casts),
        }
}

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
