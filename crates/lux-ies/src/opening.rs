//! The luminous opening: its shape follows from the signs of width, length and height
//! (LM-63-2002 Annex, "Luminous shapes").

/// Shape of the luminous opening. Dimensions are in the file's units, as positive magnitudes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LuminousOpening {
    /// w = l = h = 0.
    Point,
    /// w > 0, l > 0, h = 0.
    Rectangle {
        /// Width (along the 90°–270° axis).
        width: f64,
        /// Length (along the 0°–180° axis).
        length: f64,
    },
    /// w > 0, l > 0, h > 0: a box with luminous sides.
    RectangleWithSides {
        /// Width.
        width: f64,
        /// Length.
        length: f64,
        /// Height.
        height: f64,
    },
    /// w < 0, l < 0 equal, h = 0.
    Circle {
        /// Diameter |w|.
        diameter: f64,
    },
    /// w < 0, l < 0 different, h = 0.
    Ellipse {
        /// |w|.
        width: f64,
        /// |l|.
        length: f64,
    },
    /// w < 0, l < 0 equal, h > 0.
    VerticalCylinder {
        /// |w|.
        diameter: f64,
        /// h.
        height: f64,
    },
    /// w < 0, l < 0 different, h > 0.
    VerticalEllipticalCylinder {
        /// |w|.
        width: f64,
        /// |l|.
        length: f64,
        /// h.
        height: f64,
    },
    /// w, l, h < 0 all equal.
    Sphere {
        /// |w|.
        diameter: f64,
    },
    /// w, l, h < 0 not all equal.
    Ellipsoid {
        /// |w|.
        width: f64,
        /// |l|.
        length: f64,
        /// |h|.
        height: f64,
    },
    /// w < 0, l > 0, h < 0 (|w| = |h|): cylinder along the 0°–180° (length) axis.
    HorizontalCylinderAlongLength {
        /// |w|.
        diameter: f64,
        /// l.
        length: f64,
    },
    /// w > 0, l < 0, h < 0 (|l| = |h|): cylinder along the 90°–270° (width) axis.
    HorizontalCylinderAlongWidth {
        /// w.
        width: f64,
        /// |l|.
        diameter: f64,
    },
    /// Any other sign combination (not defined by the annex).
    Other {
        /// w as written.
        width: f64,
        /// l as written.
        length: f64,
        /// h as written.
        height: f64,
    },
}

impl LuminousOpening {
    /// Classifies width, length, height as written in the file (LM-63-2002 Annex D sign rules).
    pub fn from_dimensions(w: f64, l: f64, h: f64) -> LuminousOpening {
        use LuminousOpening::*;
        let (aw, al, ah) = (w.abs(), l.abs(), h.abs());
        if w == 0.0 && l == 0.0 && h == 0.0 {
            Point
        } else if w > 0.0 && l > 0.0 && h == 0.0 {
            Rectangle {
                width: w,
                length: l,
            }
        } else if w > 0.0 && l > 0.0 && h > 0.0 {
            RectangleWithSides {
                width: w,
                length: l,
                height: h,
            }
        } else if w < 0.0 && l < 0.0 && h == 0.0 {
            if aw == al {
                Circle { diameter: aw }
            } else {
                Ellipse {
                    width: aw,
                    length: al,
                }
            }
        } else if w < 0.0 && l < 0.0 && h > 0.0 {
            if aw == al {
                VerticalCylinder {
                    diameter: aw,
                    height: h,
                }
            } else {
                VerticalEllipticalCylinder {
                    width: aw,
                    length: al,
                    height: h,
                }
            }
        } else if w < 0.0 && l < 0.0 && h < 0.0 {
            if aw == al && al == ah {
                Sphere { diameter: aw }
            } else {
                Ellipsoid {
                    width: aw,
                    length: al,
                    height: ah,
                }
            }
        } else if w < 0.0 && l > 0.0 && h < 0.0 {
            HorizontalCylinderAlongLength {
                diameter: aw,
                length: l,
            }
        } else if w > 0.0 && l < 0.0 && h < 0.0 {
            HorizontalCylinderAlongWidth {
                width: w,
                diameter: al,
            }
        } else {
            Other {
                width: w,
                length: l,
                height: h,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::LuminousOpening::*;
    use super::*;

    #[test]
    fn annex_sign_table() {
        let f = LuminousOpening::from_dimensions;
        assert_eq!(f(0.0, 0.0, 0.0), Point);
        assert_eq!(
            f(1.0, 2.0, 0.0),
            Rectangle {
                width: 1.0,
                length: 2.0
            }
        );
        assert_eq!(
            f(1.0, 2.0, 3.0),
            RectangleWithSides {
                width: 1.0,
                length: 2.0,
                height: 3.0
            }
        );
        assert_eq!(f(-1.0, -1.0, 0.0), Circle { diameter: 1.0 });
        assert_eq!(
            f(-1.0, -2.0, 0.0),
            Ellipse {
                width: 1.0,
                length: 2.0
            }
        );
        assert_eq!(
            f(-1.0, -1.0, 1.0),
            VerticalCylinder {
                diameter: 1.0,
                height: 1.0
            }
        );
        assert_eq!(
            f(-1.0, -2.0, 1.0),
            VerticalEllipticalCylinder {
                width: 1.0,
                length: 2.0,
                height: 1.0
            }
        );
        assert_eq!(f(-1.0, -1.0, -1.0), Sphere { diameter: 1.0 });
        assert_eq!(
            f(-1.0, -2.0, -1.0),
            Ellipsoid {
                width: 1.0,
                length: 2.0,
                height: 1.0
            }
        );
        assert_eq!(
            f(-1.0, 2.0, -1.0),
            HorizontalCylinderAlongLength {
                diameter: 1.0,
                length: 2.0
            }
        );
        assert_eq!(
            f(2.0, -1.0, -1.0),
            HorizontalCylinderAlongWidth {
                width: 2.0,
                diameter: 1.0
            }
        );
        assert!(matches!(f(1.0, -1.0, 0.0), Other { .. }));
    }
}
