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
    /// w < 0, l > 0, h < 0 with |w| = |h|: "horizontal cylinder along photometric horizontal",
    /// its axis along the 0°–180° (length) direction.
    HorizontalCylinderAlongLength {
        /// |w|.
        diameter: f64,
        /// l.
        length: f64,
    },
    /// w < 0, l > 0, h < 0 with |w| ≠ |h|: "horizontal ellipsoidal cylinder along photometric
    /// horizontal".
    HorizontalEllipticalCylinderAlongLength {
        /// |w|.
        width: f64,
        /// l.
        length: f64,
        /// |h|.
        height: f64,
    },
    /// w > 0, l < 0, h < 0 with |l| = |h|: "horizontal cylinder perpendicular to photometric
    /// horizontal", its axis along the 90°–270° (width) direction.
    HorizontalCylinderAlongWidth {
        /// w.
        width: f64,
        /// |l|.
        diameter: f64,
    },
    /// w > 0, l < 0, h < 0 with |l| ≠ |h|: "horizontal ellipsoidal cylinder perpendicular to
    /// photometric horizontal".
    HorizontalEllipticalCylinderAlongWidth {
        /// w.
        width: f64,
        /// |l|.
        length: f64,
        /// |h|.
        height: f64,
    },
    /// w < 0, l = 0, h < 0 with |w| = |h|: "vertical circle facing photometric horizontal".
    VerticalCircle {
        /// |w|.
        diameter: f64,
    },
    /// w < 0, l = 0, h < 0 with |w| ≠ |h|: "vertical ellipse facing photometric horizontal".
    VerticalEllipse {
        /// |w|.
        width: f64,
        /// |h|.
        height: f64,
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
    /// Classifies width, length, height as written in the file by the sign rules of the
    /// LM-63-2002 annex "luminous shapes" (15 shapes; zero, positive and negative dimensions
    /// select the shape, equal magnitudes distinguish circles/cylinders/spheres from their
    /// elliptical versions). A sign pattern the annex does not define gives [`Self::Other`].
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
            if aw == ah {
                HorizontalCylinderAlongLength {
                    diameter: aw,
                    length: l,
                }
            } else {
                HorizontalEllipticalCylinderAlongLength {
                    width: aw,
                    length: l,
                    height: ah,
                }
            }
        } else if w > 0.0 && l < 0.0 && h < 0.0 {
            if al == ah {
                HorizontalCylinderAlongWidth {
                    width: w,
                    diameter: al,
                }
            } else {
                HorizontalEllipticalCylinderAlongWidth {
                    width: w,
                    length: al,
                    height: ah,
                }
            }
        } else if w < 0.0 && l == 0.0 && h < 0.0 {
            if aw == ah {
                VerticalCircle { diameter: aw }
            } else {
                VerticalEllipse {
                    width: aw,
                    height: ah,
                }
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

    /// The full table of lidrs' `test_get_luminous_opening` (sammorrell/lidrs @ 9aa5cef5,
    /// src/io/ies/tests.rs, MIT), in its order, with lidrs' variant names mapped to ours.
    #[test]
    fn lidrs_luminous_opening_table() {
        let f = LuminousOpening::from_dimensions;
        assert_eq!(f(0.0, 0.0, 0.0), Point);
        assert_eq!(
            f(1.0, 1.0, 0.0),
            Rectangle {
                width: 1.0,
                length: 1.0
            }
        );
        assert_eq!(
            f(1.0, 1.0, 1.0),
            RectangleWithSides {
                width: 1.0,
                length: 1.0,
                height: 1.0
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
            f(-1.0, -1.0, -2.0),
            Ellipsoid {
                width: 1.0,
                length: 1.0,
                height: 2.0
            }
        );
        assert_eq!(
            f(-3.0, -1.0, -2.0),
            Ellipsoid {
                width: 3.0,
                length: 1.0,
                height: 2.0
            }
        );
        assert_eq!(
            f(-1.0, 1.0, -1.0),
            HorizontalCylinderAlongLength {
                diameter: 1.0,
                length: 1.0
            }
        );
        assert_eq!(
            f(-1.0, 1.0, -2.0),
            HorizontalEllipticalCylinderAlongLength {
                width: 1.0,
                length: 1.0,
                height: 2.0
            }
        );
        assert_eq!(
            f(1.0, -1.0, -1.0),
            HorizontalCylinderAlongWidth {
                width: 1.0,
                diameter: 1.0
            }
        );
        assert_eq!(
            f(1.0, -1.0, -2.0),
            HorizontalEllipticalCylinderAlongWidth {
                width: 1.0,
                length: 1.0,
                height: 2.0
            }
        );
        assert_eq!(f(-1.0, 0.0, -1.0), VerticalCircle { diameter: 1.0 });
        assert_eq!(
            f(-1.0, 0.0, -2.0),
            VerticalEllipse {
                width: 1.0,
                height: 2.0
            }
        );
        // Sign patterns outside the annex.
        assert!(matches!(f(1.0, -1.0, 0.0), Other { .. }));
        assert!(matches!(f(0.0, 1.0, 0.0), Other { .. }));
        assert!(matches!(f(f64::NAN, 1.0, 0.0), Other { .. }));
    }
}
