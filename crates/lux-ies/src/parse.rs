//! The LM-63 reader: version line, keyword block, TILT, header numbers, angles and candela.

use crate::edition::Edition;
use crate::error::{IesError, Position};
use crate::file::{IesFile, PhotometricType, Units};
use crate::header::{HeaderLine, split_keyword};
use crate::lexer::Lexer;
use crate::tilt::{LampGeometry, Tilt, TiltData};
use crate::warning::Warning;

/// Largest angle count accepted per axis (real files have at most a few hundred).
pub const MAX_ANGLES: u64 = 100_000;
/// Largest number of candela values accepted (`n_h × n_v`).
pub const MAX_VALUES: u64 = 20_000_000;
/// Largest number of tilt angles accepted.
pub const MAX_TILT_ANGLES: u64 = 10_000;

/// Supplies the text of `TILT=<file>` files: called with the name as written; `None` = not found.
pub type TiltResolver<'r> = &'r dyn Fn(&str) -> Option<String>;

/// Options for [`IesFile::parse_with`].
#[derive(Clone, Copy, Default)]
pub struct ParseOptions<'r> {
    /// Loads `TILT=<file>` files. Without one, such files parse with `Tilt::File { data: None }`.
    pub tilt_resolver: Option<TiltResolver<'r>>,
    /// Make an unresolvable `TILT=<file>` an error ([`IesError::TiltFileMissing`]) instead of a
    /// warning.
    pub require_tilt_file: bool,
    /// Accept two common deviations with a warning instead of refusing the file: integer fields
    /// written as decimals (`2.0` for a count or a code; [`Warning::IntegerWrittenAsDecimal`])
    /// and numbers after the last candela value ([`Warning::TrailingData`]). Off by default:
    /// LM-63 integer fields are integers (appleseed's reader refuses `2.0` too) and extra numbers
    /// mean the header counts do not match the data ([`IesError::CountMismatch`]).
    pub lenient: bool,
}

impl core::fmt::Debug for ParseOptions<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("ParseOptions")
            .field("tilt_resolver", &self.tilt_resolver.is_some())
            .field("require_tilt_file", &self.require_tilt_file)
            .field("lenient", &self.lenient)
            .finish()
    }
}

/// A parsed file with the non-fatal findings.
#[derive(Clone, Debug, PartialEq)]
pub struct Parsed {
    /// The file.
    pub file: IesFile,
    /// Warnings, in file order.
    pub warnings: Vec<Warning>,
}

impl IesFile {
    /// Parses LM-63 text of any edition with default options (no TILT file resolver).
    pub fn parse(text: &str) -> Result<IesFile, IesError> {
        Self::parse_with(text, &ParseOptions::default()).map(|p| p.file)
    }

    /// Parses LM-63 text of any edition, returning the file and its warnings.
    pub fn parse_with(text: &str, options: &ParseOptions<'_>) -> Result<Parsed, IesError> {
        parse(text, options)
    }
}

fn is_tilt_line(line: &str) -> Option<&str> {
    let t = line.trim_start();
    if t.len() < 4 || !t.is_char_boundary(4) || !t[..4].eq_ignore_ascii_case("TILT") {
        return None;
    }
    let rest = t[4..].trim_start();
    rest.strip_prefix('=').map(str::trim)
}

fn parse(text: &str, options: &ParseOptions<'_>) -> Result<Parsed, IesError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut warnings = Vec::new();
    let mut header: Vec<HeaderLine> = Vec::new();
    let mut edition = None;
    let mut offset = 0usize;
    let mut line_no = 0usize;
    let mut tilt_value: Option<(&str, usize)> = None;
    for raw in text.split_inclusive('\n') {
        line_no += 1;
        offset += raw.len();
        let line = raw.trim_end_matches(['\n', '\r']);
        if line_no == 1
            && let Some(e) = Edition::detect(line)
        {
            edition = Some(e);
            continue;
        }
        if let Some(v) = is_tilt_line(line) {
            tilt_value = Some((v, line_no));
            break;
        }
        let trimmed = line.trim();
        if trimmed.is_empty() {
            continue;
        }
        match split_keyword(trimmed) {
            Some((name, value)) if name.eq_ignore_ascii_case("MORE") => {
                if let Some(HeaderLine::Keyword { value: prev, .. }) = header.last_mut() {
                    prev.push('\n');
                    prev.push_str(value);
                } else {
                    warnings.push(Warning::OrphanMore { line: line_no });
                    header.push(HeaderLine::Keyword {
                        name: name.to_owned(),
                        value: value.to_owned(),
                    });
                }
            }
            Some((name, value)) => header.push(HeaderLine::Keyword {
                name: name.to_owned(),
                value: value.to_owned(),
            }),
            None => {
                if edition.is_some() {
                    warnings.push(Warning::NonKeywordLine { line: line_no });
                }
                header.push(HeaderLine::Text(trimmed.to_owned()));
            }
        }
    }
    let edition = edition.unwrap_or(Edition::Lm63_1986);
    let Some((tilt_text, tilt_line)) = tilt_value else {
        return Err(IesError::MissingTilt {
            at: Position::new(line_no.max(1), 1),
        });
    };
    for req in edition.required_keywords() {
        if crate::header::find(&header, req).is_none() {
            warnings.push(Warning::MissingKeyword {
                edition,
                name: (*req).to_owned(),
            });
        }
    }
    let tilt_at = Position::new(tilt_line, 1);
    let mut lx = Lexer::new(&text[offset..], tilt_line + 1, 1);
    let tilt = if tilt_text.eq_ignore_ascii_case("NONE") {
        Tilt::None
    } else if tilt_text.eq_ignore_ascii_case("INCLUDE") {
        Tilt::Include(parse_tilt_block(&mut lx, &mut warnings, options.lenient)?)
    } else {
        let name = tilt_text.to_owned();
        let resolved = options.tilt_resolver.and_then(|r| r(&name));
        match resolved {
            Some(content) => {
                let mut tl = Lexer::new(&content, 1, 1);
                let mut inner_w = Vec::new();
                let data =
                    parse_tilt_block(&mut tl, &mut inner_w, options.lenient).map_err(|e| {
                        IesError::TiltFile {
                            at: tilt_at,
                            name: name.clone(),
                            inner: Box::new(e),
                        }
                    })?;
                Tilt::File {
                    name,
                    data: Some(data),
                }
            }
            None if options.require_tilt_file => {
                return Err(IesError::TiltFileMissing { at: tilt_at, name });
            }
            None => {
                warnings.push(Warning::TiltFileUnresolved {
                    line: tilt_line,
                    name: name.clone(),
                });
                Tilt::File { name, data: None }
            }
        }
    };

    let lenient = options.lenient;
    let int = |lx: &mut Lexer<'_>, field: &'static str, w: &mut Vec<Warning>| {
        let (v, at, decorated) = lx.integer(&|| field.to_owned())?;
        if decorated {
            decimal_integer(at, field, v, lenient, w)?;
        }
        Ok::<_, IesError>((v, at))
    };
    let real = |lx: &mut Lexer<'_>, field: &'static str| lx.real(&|| field.to_owned());

    let (lamp_count, at) = int(&mut lx, "number of lamps", &mut warnings)?;
    if !(0..=1_000_000).contains(&lamp_count) {
        return Err(IesError::InvalidValue {
            at,
            field: "number of lamps",
            value: lamp_count.to_string(),
            expected: "0 to 1000000".into(),
        });
    }
    let (lumens_per_lamp, at) = real(&mut lx, "lumens per lamp")?;
    if lumens_per_lamp < 0.0 && lumens_per_lamp != -1.0 {
        warnings.push(Warning::NegativeLumens {
            at,
            value: lumens_per_lamp,
        });
    }
    let (candela_multiplier, at) = real(&mut lx, "candela multiplier")?;
    non_negative(candela_multiplier, at, "candela multiplier")?;
    let (nv, nv_at) = int(&mut lx, "number of vertical angles", &mut warnings)?;
    let (nh, nh_at) = int(&mut lx, "number of horizontal angles", &mut warnings)?;
    let nv = count(nv, nv_at, "number of vertical angles", MAX_ANGLES)?;
    let nh = count(nh, nh_at, "number of horizontal angles", MAX_ANGLES)?;
    if nv < 2 {
        return Err(IesError::InvalidValue {
            at: nv_at,
            field: "number of vertical angles",
            value: nv.to_string(),
            expected: "at least 2".into(),
        });
    }
    if (nv as u64) * (nh as u64) > MAX_VALUES {
        return Err(IesError::AbsurdCount {
            at: nh_at,
            field: "number of candela values",
            value: (nv as u64) * (nh as u64),
            max: MAX_VALUES,
        });
    }
    let (pt, at) = int(&mut lx, "photometric type", &mut warnings)?;
    let photometric_type =
        PhotometricType::from_code(pt).ok_or_else(|| IesError::InvalidValue {
            at,
            field: "photometric type",
            value: pt.to_string(),
            expected: "1 (type C), 2 (type B) or 3 (type A)".into(),
        })?;
    let (ut, at) = int(&mut lx, "units type", &mut warnings)?;
    let units = Units::from_code(ut).ok_or_else(|| IesError::InvalidValue {
        at,
        field: "units type",
        value: ut.to_string(),
        expected: "1 (feet) or 2 (meters)".into(),
    })?;
    let (width, _) = real(&mut lx, "luminous opening width")?;
    let (length, _) = real(&mut lx, "luminous opening length")?;
    let (height, _) = real(&mut lx, "luminous opening height")?;
    let (ballast_factor, at) = real(&mut lx, "ballast factor")?;
    non_negative(ballast_factor, at, "ballast factor")?;
    let (third_factor, _) = real(
        &mut lx,
        if edition == Edition::Lm63_2019 {
            "file generation type"
        } else {
            "ballast-lamp photometric factor"
        },
    )?;
    let (input_watts, _) = real(&mut lx, "input watts")?;

    let cap = |n: usize, lx: &Lexer<'_>| n.min(lx.remaining() / 2 + 1);
    let mut vertical_angles = Vec::with_capacity(cap(nv, &lx));
    let mut v_pos = Vec::with_capacity(cap(nv, &lx));
    for i in 0..nv {
        let (a, at) = lx.real(&|| format!("vertical angle {} of {nv}", i + 1))?;
        vertical_angles.push(a);
        v_pos.push(at);
    }
    let mut horizontal_angles = Vec::with_capacity(cap(nh, &lx));
    let mut h_pos = Vec::with_capacity(cap(nh, &lx));
    for i in 0..nh {
        let (a, at) = lx.real(&|| format!("horizontal angle {} of {nh}", i + 1))?;
        horizontal_angles.push(a);
        h_pos.push(at);
    }
    check_angles(
        photometric_type,
        &vertical_angles,
        &|i| v_pos[i],
        &horizontal_angles,
        &|i| h_pos[i],
    )?;
    let mut candela = Vec::with_capacity(cap(nv * nh, &lx));
    for (h, &h_angle) in horizontal_angles.iter().enumerate() {
        for v in 0..nv {
            let (c, at) = lx.real(&|| {
                format!(
                    "candela value {} of {nv} for horizontal angle {} ({} of {nh})",
                    v + 1,
                    h_angle,
                    h + 1
                )
            })?;
            if c < 0.0 {
                return Err(IesError::InvalidValue {
                    at,
                    field: "candela value",
                    value: c.to_string(),
                    expected: "a non-negative candela value".into(),
                });
            }
            candela.push(c);
        }
    }
    if let Some(tok) = lx.next_token() {
        if crate::lexer::parse_number(tok.text).is_some() && !lenient {
            return Err(IesError::CountMismatch {
                at: tok.at,
                found: tok.text.chars().take(40).collect(),
                expected: format!(
                    "{nh} × {nv} = {} candela values the header declares",
                    nh * nv
                ),
            });
        }
        warnings.push(Warning::TrailingData { at: tok.at });
    }
    Ok(Parsed {
        file: IesFile {
            edition,
            header,
            tilt,
            lamp_count,
            lumens_per_lamp,
            candela_multiplier,
            photometric_type,
            units,
            width,
            length,
            height,
            ballast_factor,
            third_factor,
            input_watts,
            vertical_angles_deg: vertical_angles,
            horizontal_angles_deg: horizontal_angles,
            candela,
        },
        warnings,
    })
}

fn non_negative(v: f64, at: Position, field: &'static str) -> Result<(), IesError> {
    if v < 0.0 {
        return Err(IesError::InvalidValue {
            at,
            field,
            value: v.to_string(),
            expected: "a non-negative number".into(),
        });
    }
    Ok(())
}

fn count(v: i64, at: Position, field: &'static str, max: u64) -> Result<usize, IesError> {
    if v < 1 {
        return Err(IesError::InvalidValue {
            at,
            field,
            value: v.to_string(),
            expected: "a positive count".into(),
        });
    }
    if v as u64 > max {
        return Err(IesError::AbsurdCount {
            at,
            field,
            value: v as u64,
            max,
        });
    }
    Ok(v as usize)
}

/// An integer field written as `2.0` / `2e0`: an error, or a warning when `lenient`.
fn decimal_integer(
    at: Position,
    field: &'static str,
    value: i64,
    lenient: bool,
    w: &mut Vec<Warning>,
) -> Result<(), IesError> {
    if lenient {
        w.push(Warning::IntegerWrittenAsDecimal { at, field });
        Ok(())
    } else {
        Err(IesError::InvalidValue {
            at,
            field,
            value: value.to_string(),
            expected: "an integer written without a decimal point or exponent".into(),
        })
    }
}

fn parse_tilt_block(
    lx: &mut Lexer<'_>,
    w: &mut Vec<Warning>,
    lenient: bool,
) -> Result<TiltData, IesError> {
    let (g, at, dec) = lx.integer(&|| "lamp-to-luminaire geometry".into())?;
    if dec {
        decimal_integer(at, "lamp-to-luminaire geometry", g, lenient, w)?;
    }
    let geometry = LampGeometry::from_code(g).ok_or_else(|| IesError::InvalidValue {
        at,
        field: "lamp-to-luminaire geometry",
        value: g.to_string(),
        expected: "1, 2 or 3".into(),
    })?;
    let (n, at, dec) = lx.integer(&|| "number of tilt angles".into())?;
    if dec {
        decimal_integer(at, "number of tilt angles", n, lenient, w)?;
    }
    let n = count(n, at, "number of tilt angles", MAX_TILT_ANGLES)?;
    let cap = n.min(lx.remaining() / 2 + 1);
    let mut angles = Vec::with_capacity(cap);
    for i in 0..n {
        let (a, at) = lx.real(&|| format!("tilt angle {} of {n}", i + 1))?;
        if let Some(&prev) = angles.last()
            && a <= prev
        {
            return Err(IesError::NonMonotonic {
                at,
                field: "tilt",
                previous: prev,
                value: a,
            });
        }
        angles.push(a);
    }
    let mut factors = Vec::with_capacity(cap);
    for i in 0..n {
        let (f, at) = lx.real(&|| format!("tilt multiplying factor {} of {n}", i + 1))?;
        non_negative(f, at, "tilt multiplying factor")?;
        factors.push(f);
    }
    Ok(TiltData {
        geometry,
        angles_deg: angles,
        factors,
    })
}

/// Checks strict monotonicity and the LM-63 angle ranges:
/// type C vertical within 0..180 (any sub-range, e.g. 0..90, 90..180, 130..180), horizontal a
/// single plane at 0, or 0..90, 0..180, 0..(180, 360], or 90..270 (LM-63-1995 bilateral);
/// types A and B vertical within −90..90, horizontal a single plane at 0, 0..90 or −90..90.
pub(crate) fn check_angles(
    ptype: PhotometricType,
    v: &[f64],
    v_at: &dyn Fn(usize) -> Position,
    h: &[f64],
    h_at: &dyn Fn(usize) -> Position,
) -> Result<(), IesError> {
    for (field, a, at) in [("vertical", v, v_at), ("horizontal", h, h_at)] {
        for i in 1..a.len() {
            if a[i] <= a[i - 1] {
                return Err(IesError::NonMonotonic {
                    at: at(i),
                    field,
                    previous: a[i - 1],
                    value: a[i],
                });
            }
        }
    }
    let err =
        |field, a: &[f64], at: &dyn Fn(usize) -> Position, expected| IesError::IllegalAngleRange {
            at: at(0),
            field,
            first: a[0],
            last: a[a.len() - 1],
            ptype: ptype.letter(),
            expected,
        };
    if v.len() < 2 {
        return Err(IesError::Inconsistent {
            at: Position::default(),
            what: "at least 2 vertical angles are needed".into(),
        });
    }
    if h.is_empty() {
        return Err(IesError::Inconsistent {
            at: Position::default(),
            what: "at least 1 horizontal angle is needed".into(),
        });
    }
    let (v0, v1) = (v[0], v[v.len() - 1]);
    let (h0, h1) = (h[0], h[h.len() - 1]);
    match ptype {
        PhotometricType::C => {
            if !(v0 >= 0.0 && v1 <= 180.0) {
                return Err(err("vertical", v, v_at, "angles within 0..180"));
            }
            let ok = if h.len() == 1 {
                h0 == 0.0
            } else if h0 == 0.0 {
                h1 == 90.0 || (180.0..=360.0).contains(&h1)
            } else {
                h0 == 90.0 && h1 == 270.0
            };
            if !ok {
                return Err(err(
                    "horizontal",
                    h,
                    h_at,
                    "a single plane at 0, or 0..90, 0..180, 0..360 or 90..270",
                ));
            }
        }
        PhotometricType::A | PhotometricType::B => {
            if !(v0 >= -90.0 && v1 <= 90.0) {
                return Err(err("vertical", v, v_at, "angles within -90..90"));
            }
            let ok = if h.len() == 1 {
                h0 == 0.0
            } else {
                (h0 == 0.0 || h0 == -90.0) && h1 == 90.0
            };
            if !ok {
                return Err(err(
                    "horizontal",
                    h,
                    h_at,
                    "a single plane at 0, or 0..90, or -90..90",
                ));
            }
        }
    }
    Ok(())
}
