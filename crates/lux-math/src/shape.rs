//! Light kinds and their geometric inputs, with the UsdLux 26.11 schema defaults.

use glam::DVec3;

/// The built-in UsdLux light families (closed set).
///
/// `Mesh` is a gprim with `MeshLightAPI` applied; `Dome` covers `DomeLight` and `DomeLight_1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LightKind {
    /// `DistantLight`: directional, `inputs:angle` degrees wide, emits along local −Z.
    Distant,
    /// `DomeLight` / `DomeLight_1`: light from infinitely far away in every direction.
    Dome,
    /// `PortalLight`: a rectangular window (XY plane) guiding a dome light.
    Portal,
    /// `RectLight`: a `width` × `height` rectangle in local XY, emitting from its −Z side.
    Rect,
    /// `DiskLight`: a disk of `radius` in local XY, emitting from its −Z side.
    Disk,
    /// `SphereLight`: a sphere of `radius`, emitting outward from its whole surface.
    Sphere,
    /// `CylinderLight`: lateral surface of a cylinder along local X (`length`, `radius`), no caps.
    Cylinder,
    /// A mesh with `MeshLightAPI`: every triangle emits from its front side.
    Mesh,
}

impl LightKind {
    /// Every kind, in declaration order.
    pub const ALL: [LightKind; 8] = [
        LightKind::Distant,
        LightKind::Dome,
        LightKind::Portal,
        LightKind::Rect,
        LightKind::Disk,
        LightKind::Sphere,
        LightKind::Cylinder,
        LightKind::Mesh,
    ];

    /// The USD schema type name (`"MeshLightAPI"` for mesh lights).
    pub const fn usd_type_name(self) -> &'static str {
        match self {
            LightKind::Distant => "DistantLight",
            LightKind::Dome => "DomeLight",
            LightKind::Portal => "PortalLight",
            LightKind::Rect => "RectLight",
            LightKind::Disk => "DiskLight",
            LightKind::Sphere => "SphereLight",
            LightKind::Cylinder => "CylinderLight",
            LightKind::Mesh => "MeshLightAPI",
        }
    }

    /// Whether `inputs:normalize` divides by a world-space surface area (the "area lights" of the
    /// normalize doc: mesh, disk, rect, sphere, cylinder).
    pub const fn is_area(self) -> bool {
        matches!(
            self,
            LightKind::Rect
                | LightKind::Disk
                | LightKind::Sphere
                | LightKind::Cylinder
                | LightKind::Mesh
        )
    }
}

/// The geometric inputs of a light, in its local space (before the light-to-world transform).
///
/// Field names follow the schema attributes: `inputs:width`, `inputs:height`, `inputs:radius`,
/// `inputs:length`, `inputs:angle` (degrees). Mesh triangles are the mesh's local-space points.
#[derive(Clone, Debug, PartialEq)]
pub enum LightShape {
    /// `DistantLight.inputs:angle`, the angular **diameter** in degrees (default 0.53).
    Distant {
        /// `inputs:angle` in degrees.
        angle_deg: f64,
    },
    /// `DomeLight`: no geometry.
    Dome,
    /// `PortalLight.inputs:width` × `inputs:height` (defaults 1 × 1).
    Portal {
        /// `inputs:width`, along local X.
        width: f64,
        /// `inputs:height`, along local Y.
        height: f64,
    },
    /// `RectLight.inputs:width` × `inputs:height` (defaults 1 × 1).
    Rect {
        /// `inputs:width`, along local X.
        width: f64,
        /// `inputs:height`, along local Y.
        height: f64,
    },
    /// `DiskLight.inputs:radius` (default 0.5).
    Disk {
        /// `inputs:radius`.
        radius: f64,
    },
    /// `SphereLight.inputs:radius` (default 0.5).
    Sphere {
        /// `inputs:radius`.
        radius: f64,
    },
    /// `CylinderLight.inputs:radius` (default 0.5) and `inputs:length` (default 1) along local X.
    Cylinder {
        /// `inputs:radius`.
        radius: f64,
        /// `inputs:length`, along local X.
        length: f64,
    },
    /// A `MeshLightAPI` gprim's triangles in its local space.
    Mesh {
        /// Local-space triangles.
        triangles: Vec<[DVec3; 3]>,
    },
}

impl LightShape {
    /// The schema defaults of `kind` (an empty triangle list for meshes).
    pub fn default_for(kind: LightKind) -> LightShape {
        match kind {
            LightKind::Distant => LightShape::Distant { angle_deg: 0.53 },
            LightKind::Dome => LightShape::Dome,
            LightKind::Portal => LightShape::Portal {
                width: 1.0,
                height: 1.0,
            },
            LightKind::Rect => LightShape::Rect {
                width: 1.0,
                height: 1.0,
            },
            LightKind::Disk => LightShape::Disk { radius: 0.5 },
            LightKind::Sphere => LightShape::Sphere { radius: 0.5 },
            LightKind::Cylinder => LightShape::Cylinder {
                radius: 0.5,
                length: 1.0,
            },
            LightKind::Mesh => LightShape::Mesh {
                triangles: Vec::new(),
            },
        }
    }

    /// The light family of this shape.
    pub fn kind(&self) -> LightKind {
        match self {
            LightShape::Distant { .. } => LightKind::Distant,
            LightShape::Dome => LightKind::Dome,
            LightShape::Portal { .. } => LightKind::Portal,
            LightShape::Rect { .. } => LightKind::Rect,
            LightShape::Disk { .. } => LightKind::Disk,
            LightShape::Sphere { .. } => LightKind::Sphere,
            LightShape::Cylinder { .. } => LightKind::Cylinder,
            LightShape::Mesh { .. } => LightKind::Mesh,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_follow_schema() {
        assert_eq!(
            LightShape::default_for(LightKind::Distant),
            LightShape::Distant { angle_deg: 0.53 }
        );
        assert_eq!(
            LightShape::default_for(LightKind::Cylinder),
            LightShape::Cylinder {
                radius: 0.5,
                length: 1.0
            }
        );
        for k in LightKind::ALL {
            assert_eq!(LightShape::default_for(k).kind(), k);
        }
        assert!(LightKind::Mesh.is_area() && !LightKind::Portal.is_area());
        assert_eq!(LightKind::Rect.usd_type_name(), "RectLight");
    }
}
