//! The camera: a `UsdGeomCamera` with the render's resolution, pixel aspect ratio and data
//! window turned into a pinhole (perspective) or parallel (orthographic) ray generator.
//!
//! Conventions (UsdGeomCamera / GfCamera): the camera looks down its local −Z with +Y up; the
//! film window is `horizontalAperture × verticalAperture`, shifted by the aperture offsets; a
//! perspective camera's window lies at distance `focalLength` (only the ratios matter), an
//! orthographic camera's window is the aperture in tenths of a scene unit (GfCamera's
//! `APERTURE_UNIT` 0.1). When the window's aspect differs from the image's
//! (`width · pixelAspectRatio / height`), the window is expanded about its centre in the
//! direction that is too small (UsdRenderSettings `aspectRatioConformPolicy` =
//! `"expandAperture"`, the schema default).
//!
//! Pixel (x, y) covers `[x, x+1) × [y, y+1)` with y = 0 the **top** row; a sample at continuous
//! coordinates (x + jx, y + jy) maps linearly onto the window (box pixel filter).

use glam::{DMat3, DMat4, DVec3, DVec4};
use lux_usd::Projection;

/// The orthographic aperture unit of GfCamera: apertures are in tenths of a scene unit.
pub const APERTURE_UNIT: f64 = 0.1;

/// A camera ready to generate rays for an image of `width × height` pixels.
#[derive(Clone, Debug)]
pub struct Camera {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The pixels to render, `[x0, y0, x1, y1)` (from `dataWindowNDC`; y from the top).
    pub pixel_window: [u32; 4],
    cam_to_world: DMat4,
    /// Its inverse (world → camera space), for [`Camera::project`].
    world_to_cam: DMat4,
    /// The perspective camera's centre of projection in the world (the camera-space origin
    /// mapped by `cam_to_world`, as for every ray).
    eye: DVec3,
    ortho: bool,
    /// Film window (left, right, bottom, top): tangent units for perspective, scene units for
    /// orthographic.
    window: [f64; 4],
    near: f64,
    far: f64,
}

/// Why a camera cannot make rays.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CameraError {
    /// Non-finite or non-positive lens/aperture values, or a singular transform.
    #[error("camera {camera}: {what} (expected {expected})")]
    Invalid {
        /// Camera prim path.
        camera: String,
        /// What is wrong.
        what: String,
        /// What was expected.
        expected: &'static str,
    },
}

impl Camera {
    /// Builds the ray generator. `data_window_ndc` is `(xmin, ymin, xmax, ymax)` in NDC with
    /// (0, 0) the bottom-left corner (UsdRenderSettings `dataWindowNDC`).
    pub fn new(
        camera: &lux_usd::Camera,
        resolution: [u32; 2],
        pixel_aspect_ratio: f64,
        data_window_ndc: DVec4,
    ) -> Result<Camera, CameraError> {
        let bad = |what: String, expected: &'static str| CameraError::Invalid {
            camera: camera.path.clone(),
            what,
            expected,
        };
        let [w, h] = resolution;
        if w == 0 || h == 0 {
            return Err(bad(format!("resolution {w}×{h}"), "at least 1×1 pixels"));
        }
        if !(pixel_aspect_ratio.is_finite() && pixel_aspect_ratio > 0.0) {
            return Err(bad(
                format!("pixelAspectRatio {pixel_aspect_ratio}"),
                "a finite value > 0",
            ));
        }
        let (ha, va) = (camera.horizontal_aperture, camera.vertical_aperture);
        if !(ha.is_finite() && ha > 0.0 && va.is_finite() && va > 0.0) {
            return Err(bad(
                format!("aperture {ha} × {va}"),
                "finite horizontal/verticalAperture > 0",
            ));
        }
        let (ho, vo) = (
            camera.horizontal_aperture_offset,
            camera.vertical_aperture_offset,
        );
        if !(ho.is_finite() && vo.is_finite()) {
            return Err(bad(
                format!("aperture offsets {ho}, {vo}"),
                "finite aperture offsets",
            ));
        }
        let ortho = camera.projection == Projection::Orthographic;
        let scale = if ortho {
            APERTURE_UNIT
        } else {
            let f = camera.focal_length;
            if !(f.is_finite() && f > 0.0) {
                return Err(bad(format!("focalLength {f}"), "a finite value > 0"));
            }
            1.0 / f
        };
        let (mut l, mut r) = ((ho - 0.5 * ha) * scale, (ho + 0.5 * ha) * scale);
        let (mut b, mut t) = ((vo - 0.5 * va) * scale, (vo + 0.5 * va) * scale);
        // expandAperture: grow the dimension that is too small for the image aspect.
        let image_aspect = w as f64 * pixel_aspect_ratio / h as f64;
        let window_aspect = (r - l) / (t - b);
        if window_aspect < image_aspect {
            let (c, half) = (0.5 * (l + r), 0.5 * (t - b) * image_aspect);
            (l, r) = (c - half, c + half);
        } else if window_aspect > image_aspect {
            let (c, half) = (0.5 * (b + t), 0.5 * (r - l) / image_aspect);
            (b, t) = (c - half, c + half);
        }
        let m = camera.camera_to_world;
        if !m.is_finite() || m.determinant().abs() < 1e-300 {
            return Err(bad(
                "camera transform is singular or not finite".into(),
                "an invertible, finite transform",
            ));
        }
        let (mut near, mut far) = (camera.clipping_range.x, camera.clipping_range.y);
        if !(near.is_finite() && near >= 0.0) {
            near = 0.0;
        }
        if far.is_nan() || far <= near {
            far = f64::INFINITY;
        }
        Ok(Camera {
            width: w,
            height: h,
            pixel_window: pixel_window(w, h, data_window_ndc),
            cam_to_world: m,
            world_to_cam: m.inverse(),
            eye: m.transform_point3(DVec3::ZERO),
            ortho,
            window: [l, r, b, t],
            near,
            far,
        })
    }

    /// The ray through continuous pixel coordinates `(px, py)` (y down from the top edge):
    /// `(origin, unit direction, tmin, tmax)` in world space, with `[tmin, tmax]` the clipping
    /// range measured along the camera's view axis.
    #[inline]
    pub fn ray(&self, px: f64, py: f64) -> (DVec3, DVec3, f64, f64) {
        let [l, r, b, t] = self.window;
        let x = l + (px / self.width as f64) * (r - l);
        let y = t - (py / self.height as f64) * (t - b);
        let (o, d_cam) = if self.ortho {
            let o_cam = DVec3::new(x, y, 0.0);
            (self.cam_to_world.transform_point3(o_cam), DVec3::NEG_Z)
        } else {
            (self.eye, DVec3::new(x, y, -1.0))
        };
        let dw = self.cam_to_world.transform_vector3(d_cam);
        let len = dw.length();
        let d = dw / len;
        // Camera-space depth per unit of world distance along d: 1/len for d_cam.z = −1 under a
        // rigid camera transform; in general the ratio |d_cam.z| / |M d_cam|.
        let depth_per_t = 1.0 / len;
        (o, d, self.near / depth_per_t, self.far / depth_per_t)
    }
}

impl Camera {
    /// Where the world point `p` appears on the image, if it does: inside the film window and
    /// within the clipping range ([`CameraPoint`]; the inverse of [`Camera::ray`]).
    pub fn project(&self, p: DVec3) -> Option<CameraPoint> {
        let q = self.world_to_cam.transform_point3(p);
        let [l, r, b, t] = self.window;
        let a = DMat3::from_mat4(self.cam_to_world);
        let det = a.determinant().abs();
        let pixel_area = (r - l) / self.width as f64 * ((t - b) / self.height as f64);
        let (film, depth) = if self.ortho {
            (DVec3::new(q.x, q.y, 0.0), -q.z)
        } else {
            (DVec3::new(q.x / -q.z, q.y / -q.z, -1.0), -q.z)
        };
        if !(depth > 0.0 && depth >= self.near && depth <= self.far) {
            return None;
        }
        let px = (film.x - l) / (r - l) * self.width as f64;
        let py = (t - film.y) / (t - b) * self.height as f64;
        let inside = |v: f64, n: u32| v >= 0.0 && v < n as f64;
        if !(inside(px, self.width) && inside(py, self.height)) {
            return None;
        }
        let (o, d, importance) = if self.ortho {
            let dz = a * DVec3::NEG_Z;
            let o = self.cam_to_world.transform_point3(film);
            (o, dz.normalize(), dz.length() / (det * pixel_area))
        } else {
            let dist = (p - self.eye).length();
            let imp = dist / (depth * depth * depth * det * pixel_area);
            (self.eye, (p - self.eye) / dist, imp)
        };
        let t = (p - o).length();
        let point = CameraPoint {
            raster: [px, py],
            ray: (o, d),
            t,
            near_t: self.near * t / depth,
            importance,
        };
        (importance.is_finite() && point.t.is_finite()).then_some(point)
    }
}

impl Camera {
    /// The rays through the corners of pixels `[x0, y0, x1, y1)` (top left, top right, bottom
    /// right, bottom left) and through its centre, as `(origin, direction)` with unnormalised
    /// directions: [`Camera::ray`] maps the film linearly to directions from the eye, or to
    /// origins of parallel rays, so every ray through the rectangle lies between them. `None`
    /// for an empty rectangle.
    pub fn rect_rays(&self, [x0, y0, x1, y1]: [u32; 4]) -> Option<RectRays> {
        if x0 >= x1 || y0 >= y1 {
            return None;
        }
        let [l, r, b, t] = self.window;
        let film = |px: f64, py: f64| {
            DVec3::new(
                l + (px / self.width as f64) * (r - l),
                t - (py / self.height as f64) * (t - b),
                0.0,
            )
        };
        let (x0, y0, x1, y1) = (x0 as f64, y0 as f64, x1 as f64, y1 as f64);
        let corners = [film(x0, y0), film(x1, y0), film(x1, y1), film(x0, y1)];
        let centre = film(0.5 * (x0 + x1), 0.5 * (y0 + y1));
        let m = &self.cam_to_world;
        // (origin, direction) of the ray through a film point, unnormalised
        let ray = |f: DVec3| {
            if self.ortho {
                (m.transform_point3(f), m.transform_vector3(DVec3::NEG_Z))
            } else {
                (self.eye, m.transform_vector3(f + DVec3::NEG_Z))
            }
        };
        Some(RectRays {
            corners: corners.map(ray),
            centre: ray(centre),
        })
    }
}

/// Where a world point appears on the image ([`Camera::project`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraPoint {
    /// Continuous pixel coordinates `(x, y)` (y down from the top edge), inside the image.
    pub raster: [f64; 2],
    /// The camera ray through it: origin and unit direction (as [`Camera::ray`] makes them).
    pub ray: (DVec3, DVec3),
    /// Distance from the ray's origin to the point.
    pub t: f64,
    /// Where the ray's clipping range starts along it (`tmin` of [`Camera::ray`]).
    pub near_t: f64,
    /// The camera's importance per unit area at the point, per unit of `|n·ω|` (`n` the
    /// surface's unit normal, `ω` the ray direction): what a radiance `L` leaving a surface
    /// element `dA` towards the camera adds to the pixel, `L·|n·ω|·importance·dA`, with pixels
    /// the mean over their area of the radiance their rays bring (a box filter). Perspective:
    /// `d / (z³·|det A|·a)` for the point at distance `d` and depth `z` (camera space),
    /// `A` the camera transform's linear part and `a` the film area of a pixel at unit
    /// depth; orthographic: `|A·ẑ| / (|det A|·a)`.
    pub importance: f64,
}

/// The rays bounding a rectangle of pixels ([`Camera::rect_rays`]).
#[derive(Clone, Copy, Debug)]
pub struct RectRays {
    /// `(origin, direction)` through the corners: top left, top right, bottom right, bottom
    /// left.
    pub corners: [(DVec3, DVec3); 4],
    /// `(origin, direction)` through the centre.
    pub centre: (DVec3, DVec3),
}

/// The pixels whose centres lie in the NDC window `(xmin, ymin, xmax, ymax)` (y up), as
/// `[x0, y0, x1, y1)` with y counted from the top row.
pub fn pixel_window(w: u32, h: u32, ndc: DVec4) -> [u32; 4] {
    let (wf, hf) = (w as f64, h as f64);
    let clampx = |v: f64| {
        if v.is_nan() {
            0
        } else {
            v.clamp(0.0, wf) as u32
        }
    };
    let clampy = |v: f64| {
        if v.is_nan() {
            0
        } else {
            v.clamp(0.0, hf) as u32
        }
    };
    let x0 = clampx((wf * ndc.x - 0.5).ceil());
    let x1 = clampx((wf * ndc.z - 0.5).ceil());
    let y0 = clampy((hf * (1.0 - ndc.w) - 0.5).floor() + 1.0);
    let y1 = clampy((hf * (1.0 - ndc.y) - 0.5).floor() + 1.0);
    [x0, y0, x1.max(x0), y1.max(y0)]
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use glam::DVec2;
    use lux_usd::Camera as UsdCamera;

    pub(crate) fn luxtest_camera() -> UsdCamera {
        // The luxtest camera: 30 units above the origin looking down −Y, focal 0.5, square
        // aperture 0.20955 (rows (1,0,0), (0,0,−1), (0,1,0), translation (0,30,0)).
        UsdCamera {
            path: "/cameras/camera1".into(),
            camera_to_world: DMat4::from_cols_array(&[
                1.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 30.0, 0.0, 1.0,
            ]),
            projection: Projection::Perspective,
            focal_length: 0.5,
            horizontal_aperture: 0.20955,
            vertical_aperture: 0.20955,
            horizontal_aperture_offset: 0.0,
            vertical_aperture_offset: 0.0,
            clipping_range: DVec2::new(1.0, 1e6),
            f_stop: 0.0,
            focus_distance: 0.0,
            exposure: Default::default(),
        }
    }

    #[test]
    fn luxtest_camera_rays_hit_the_floor_where_expected() {
        let v = Camera::new(
            &luxtest_camera(),
            [512, 512],
            1.0,
            DVec4::new(0.0, 0.0, 1.0, 1.0),
        )
        .unwrap();
        assert_eq!(v.pixel_window, [0, 0, 512, 512]);
        // Centre of the image: straight down.
        let (o, d, tmin, _) = v.ray(256.0, 256.0);
        assert!((o - DVec3::new(0.0, 30.0, 0.0)).length() < 1e-12);
        assert!((d - DVec3::NEG_Y).length() < 1e-12);
        assert!((tmin - 1.0).abs() < 1e-12);
        // Right edge of the image: the floor point x = 30·(0.20955/2)/0.5 = 6.2865. The camera's
        // local +X is world +X; its local +Y (image up) is world −Z.
        let (o, d, _, _) = v.ray(512.0, 256.0);
        let p = o + d * (30.0 / -d.y);
        assert!((p - DVec3::new(6.2865, 0.0, 0.0)).length() < 1e-9, "{p}");
        let (o, d, _, _) = v.ray(256.0, 0.0);
        let p = o + d * (30.0 / -d.y);
        assert!((p - DVec3::new(0.0, 0.0, -6.2865)).length() < 1e-9, "{p}");
    }

    #[test]
    fn expand_aperture_and_orthographic() {
        let mut c = luxtest_camera();
        // 2:1 image from a square aperture: the horizontal extent doubles.
        let v = Camera::new(&c, [200, 100], 1.0, DVec4::new(0.0, 0.0, 1.0, 1.0)).unwrap();
        let (o, d, _, _) = v.ray(200.0, 50.0);
        let p = o + d * (30.0 / -d.y);
        assert!((p.x - 2.0 * 6.2865).abs() < 1e-9, "{p}");
        let (o, d, _, _) = v.ray(100.0, 0.0);
        let p = o + d * (30.0 / -d.y);
        assert!((p.z + 6.2865).abs() < 1e-9, "{p}");
        c.projection = Projection::Orthographic;
        c.horizontal_aperture = 40.0; // 4 scene units
        c.vertical_aperture = 40.0;
        let v = Camera::new(&c, [64, 64], 1.0, DVec4::new(0.0, 0.0, 1.0, 1.0)).unwrap();
        let (o, d, _, _) = v.ray(64.0, 32.0);
        assert!((d - DVec3::NEG_Y).length() < 1e-12);
        assert!((o - DVec3::new(2.0, 30.0, 0.0)).length() < 1e-12, "{o}");
    }

    #[test]
    fn data_window_pixels() {
        assert_eq!(
            pixel_window(10, 10, DVec4::new(0.0, 0.0, 1.0, 1.0)),
            [0, 0, 10, 10]
        );
        // Left half, top half (NDC y up: ymin 0.5).
        assert_eq!(
            pixel_window(10, 10, DVec4::new(0.0, 0.5, 0.5, 1.0)),
            [0, 0, 5, 5]
        );
        assert_eq!(
            pixel_window(10, 10, DVec4::new(0.5, 0.0, 1.0, 0.5)),
            [5, 5, 10, 10]
        );
        // Outside and NaN windows clamp to the image.
        assert_eq!(
            pixel_window(10, 10, DVec4::new(-1.0, -1.0, 2.0, 2.0)),
            [0, 0, 10, 10]
        );
        let p = pixel_window(10, 10, DVec4::splat(f64::NAN));
        assert!(p[2] >= p[0] && p[3] >= p[1]);
    }

    #[test]
    fn bad_cameras_are_errors() {
        let mut c = luxtest_camera();
        c.focal_length = 0.0;
        assert!(Camera::new(&c, [8, 8], 1.0, DVec4::new(0.0, 0.0, 1.0, 1.0)).is_err());
        let c = luxtest_camera();
        assert!(Camera::new(&c, [0, 8], 1.0, DVec4::new(0.0, 0.0, 1.0, 1.0)).is_err());
        assert!(Camera::new(&c, [8, 8], f64::NAN, DVec4::new(0.0, 0.0, 1.0, 1.0)).is_err());
        let mut c = luxtest_camera();
        c.camera_to_world = DMat4::ZERO;
        assert!(Camera::new(&c, [8, 8], 1.0, DVec4::new(0.0, 0.0, 1.0, 1.0)).is_err());
    }

    /// 64 × 48 cameras for `project`: the luxtest camera, perspective and orthographic, rigid
    /// and non-uniformly scaled (whether orthographic, the scale, the camera).
    fn projected_cameras() -> Vec<(bool, DVec3, Camera)> {
        let mut out = Vec::new();
        for ortho in [false, true] {
            for scale in [DVec3::ONE, DVec3::new(1.0, 2.0, 0.5)] {
                let mut c = luxtest_camera();
                c.camera_to_world *= DMat4::from_scale(scale);
                if ortho {
                    c.projection = Projection::Orthographic;
                    c.horizontal_aperture = 80.0;
                    c.vertical_aperture = 60.0;
                }
                let cam = Camera::new(&c, [64, 48], 1.0, DVec4::new(0.0, 0.0, 1.0, 1.0)).unwrap();
                out.push((ortho, scale, cam));
            }
        }
        out
    }

    /// `project` inverts `ray`: the point a pixel's ray reaches projects back to that pixel,
    /// with the ray's origin and direction, for perspective and orthographic cameras under a
    /// rigid and a non-uniformly scaled transform; points behind, outside or beyond the
    /// clipping range do not project.
    #[test]
    fn project_inverts_ray() {
        for (_, _, cam) in projected_cameras() {
            for (px, py) in [(0.5, 0.5), (13.25, 40.75), (63.9, 0.1), (32.0, 24.0)] {
                let (o, d, tmin, _) = cam.ray(px, py);
                let p = o + d * (tmin + 7.5);
                let q = cam.project(p).expect("in view");
                assert!((q.raster[0] - px).abs() < 1e-9 && (q.raster[1] - py).abs() < 1e-9);
                assert!((q.ray.0 - o).length() < 1e-9 && (q.ray.1 - d).length() < 1e-12);
                assert!((q.t - (tmin + 7.5)).abs() < 1e-9);
                assert!((q.near_t - tmin).abs() < 1e-9 * tmin.max(1.0));
            }
            let (o, d, tmin, _) = cam.ray(10.0, 10.0);
            assert!(cam.project(o - d * 5.0).is_none(), "behind");
            assert!(
                cam.project(o + d * tmin * 0.5).is_none(),
                "before the near plane"
            );
            let side = cam.cam_to_world.transform_vector3(DVec3::X);
            assert!(cam.project(o + d * 10.0 + side * 1e4).is_none(), "outside");
        }
    }

    /// The importance integrates to one pixel: a surface of unit radiance filling a pixel's
    /// view, tilted, adds `∫ |n·ω|·importance dA = 1` over the pixel's footprint (a midpoint
    /// sum over the footprint's parametrisation by the pixel's area), for perspective and
    /// orthographic cameras, rigid and scaled.
    #[test]
    fn importance_integrates_to_one_pixel() {
        for (ortho, scale, cam) in projected_cameras() {
            // A plane through (0.3, 0, 0.2) tilted away from the camera's axis.
            let n = DVec3::new(0.3, 1.0, -0.2).normalize();
            let c0 = DVec3::new(0.3, 0.0, 0.2);
            let hit = |px: f64, py: f64| {
                let (o, d, _, _) = cam.ray(px, py);
                o + d * ((c0 - o).dot(n) / d.dot(n))
            };
            for (x, y) in [(20u32, 30u32), (45, 5)] {
                let k = 64;
                let h = 1.0 / k as f64;
                let mut sum = 0.0;
                for j in 0..k {
                    for i in 0..k {
                        let (u, v) = (
                            x as f64 + (i as f64 + 0.5) * h,
                            y as f64 + (j as f64 + 0.5) * h,
                        );
                        let p = hit(u, v);
                        let du = (hit(u + 1e-4, v) - hit(u - 1e-4, v)) / 2e-4;
                        let dv = (hit(u, v + 1e-4) - hit(u, v - 1e-4)) / 2e-4;
                        let q = cam.project(p).unwrap();
                        sum += n.dot(q.ray.1).abs() * q.importance * du.cross(dv).length() * h * h;
                    }
                }
                assert!(
                    (sum - 1.0).abs() < 1e-5,
                    "ortho {ortho}, scale {scale}: {sum}"
                );
            }
        }
    }
}
