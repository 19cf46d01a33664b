//! The LM-63 writer (LM-63-2002 and LM-63-2019 output).

use crate::edition::Edition;
use crate::file::IesFile;
use crate::header::HeaderLine;
use crate::tilt::{Tilt, TiltData};
use core::fmt::Write as _;

/// Numbers per line in the angle and candela blocks (keeps lines well under LM-63's 256 chars).
const PER_LINE: usize = 10;

impl IesFile {
    /// Writes the file as LM-63 text of `edition` (the version line and the meaning of the third
    /// factor follow the target edition; everything else is written as stored).
    ///
    /// Numbers are written in Rust's shortest round-trip form, so `parse(write(x)) == x` whenever
    /// `x.edition == edition` and `x` came from a parse (or is valid and its text lines are
    /// trimmed, non-empty, and do not start with `[` or `TILT`). Converting between LM-63-2019 and
    /// an earlier edition maps the third factor: a ballast-lamp factor `f ≠ 1` is folded into the
    /// candela multiplier and the 2019 file generation type is written as 1.00001 ("undefined");
    /// going back, the factor becomes 1. `TILT=<file>` with resolved data is written as
    /// `TILT=INCLUDE`.
    pub fn write(&self, edition: Edition) -> String {
        let mut multiplier = self.candela_multiplier;
        let mut third = self.third_factor;
        match (
            self.edition == Edition::Lm63_2019,
            edition == Edition::Lm63_2019,
        ) {
            (false, true) => {
                multiplier *= self.third_factor;
                third = 1.00001;
            }
            (true, false) => third = 1.0,
            _ => {}
        }
        let mut s = String::with_capacity(64 + self.candela.len() * 8);
        if let Some(v) = edition.version_line() {
            s.push_str(v);
            s.push_str("\r\n");
        }
        for line in &self.header {
            match line {
                HeaderLine::Keyword { name, value } => {
                    for (i, part) in value.split('\n').enumerate() {
                        let key = if i == 0 { name.as_str() } else { "MORE" };
                        if part.is_empty() {
                            let _ = write!(s, "[{key}]\r\n");
                        } else {
                            let _ = write!(s, "[{key}] {part}\r\n");
                        }
                    }
                }
                HeaderLine::Text(t) => {
                    s.push_str(t);
                    s.push_str("\r\n");
                }
            }
        }
        match &self.tilt {
            Tilt::None => s.push_str("TILT=NONE\r\n"),
            Tilt::Include(d) | Tilt::File { data: Some(d), .. } => {
                s.push_str("TILT=INCLUDE\r\n");
                write_tilt(&mut s, d);
            }
            Tilt::File { name, data: None } => {
                let _ = write!(s, "TILT={name}\r\n");
            }
        }
        let _ = write!(
            s,
            "{} {} {} {} {} {} {} {} {} {}\r\n",
            self.lamp_count,
            self.lumens_per_lamp,
            multiplier,
            self.vertical_angles_deg.len(),
            self.horizontal_angles_deg.len(),
            self.photometric_type.code(),
            self.units.code(),
            self.width,
            self.length,
            self.height
        );
        let _ = write!(
            s,
            "{} {} {}\r\n",
            self.ballast_factor, third, self.input_watts
        );
        write_block(&mut s, &self.vertical_angles_deg);
        write_block(&mut s, &self.horizontal_angles_deg);
        let nv = self.vertical_angles_deg.len().max(1);
        for row in self.candela.chunks(nv) {
            write_block(&mut s, row);
        }
        s
    }
}

fn write_tilt(s: &mut String, d: &TiltData) {
    let _ = write!(s, "{}\r\n{}\r\n", d.geometry.code(), d.angles_deg.len());
    write_block(s, &d.angles_deg);
    write_block(s, &d.factors);
}

fn write_block(s: &mut String, values: &[f64]) {
    for chunk in values.chunks(PER_LINE) {
        for (i, v) in chunk.iter().enumerate() {
            if i > 0 {
                s.push(' ');
            }
            let _ = write!(s, "{v}");
        }
        s.push_str("\r\n");
    }
}
