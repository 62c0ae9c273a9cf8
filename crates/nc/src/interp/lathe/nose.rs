//! A turning tool's nose: where its imaginary tip lies from the nose centre
//! (the tip direction 0–9), and the nose centre path of a run.
//!
//! A lathe program is written to the *imaginary tool tip*: the point where
//! the two lines the tool is touched off on (its X line and its Z line)
//! meet. The nose is a circle of radius R; the imaginary tip lies off its
//! centre by R in X, in Z, or both, in the direction the tip number gives.
//! Tool nose radius compensation (`G41`/`G42`) puts the nose *centre* on
//! the programmed contour offset by R, and the machine then moves the
//! imaginary tip to that centre plus the tip vector (`docs/lathe.md`,
//! "Nose radius compensation").

use std::collections::BTreeMap;

use kezuri_geom::{Axes, Move, MoveKind, Toolpath};

use super::Nose;
use crate::interp::comp::{compensate_with_returns, Comp, Rules};
use crate::{Error, ErrorKind, Place};

/// Whose numbering a tip direction follows: the same picture, drawn with X
/// up (Fanuc and Haas) or X down (LinuxCNC's front tool post lathe).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TipNumbers {
    /// FANUC Series 0i-TF Plus Operator's Manual (B-64604EN), lathe
    /// system, "Tool nose radius compensation", "Imaginary tool nose
    /// direction"; the Haas Lathe Operator's Manual, "Imaginary Tool Tip
    /// and Direction" gives each code as a direction in X and Z.
    #[default]
    Fanuc,
    /// LinuxCNC's lathe tool orientation (the tool table's `Q`, the `L`
    /// of `G41.1`/`G42.1`): Fanuc's picture drawn with X down (its front
    /// tool post lathe), so each number names the corner Fanuc's number
    /// names with X mirrored — what `rs274` does with each orientation
    /// under `G41`/`G42` shows it (its outside turning tool is 2).
    LinuxCnc,
}

impl TipNumbers {
    /// Fanuc's tip number for the corner `tip` names in this numbering:
    /// for LinuxCNC, the Fanuc tip whose direction is `tip`'s with X
    /// mirrored (1 is 4, 2 is 3, 3 is 2, 4 is 1, 6 is 8, 8 is 6; 5, 7 and
    /// the centre's 0 and 9 stay). A number outside 0–9 is kept, for
    /// [`Nose::check`] to refuse.
    pub fn fanuc_tip(self, tip: u8) -> u8 {
        let Some(&(sx, sz)) = FANUC.get(usize::from(tip)) else { return tip };
        match self {
            TipNumbers::Fanuc => tip,
            // Tips 0 and 9 are both the centre: each stays itself.
            TipNumbers::LinuxCnc if (sx, sz) == (0.0, 0.0) => tip,
            TipNumbers::LinuxCnc => (1..=8u8).find(|&k| FANUC[usize::from(k)] == (-sx, sz)).unwrap_or(tip),
        }
    }
}

/// The direction from the nose centre to the imaginary tip for each tip
/// number, as (X, Z) signs: the tip is at centre + R·(sx, sz), X a radius.
///
/// Fanuc's figure draws the ZX plane with +Z to the right and +X up and
/// places the numbers round the nose centre like this (Haas's table says
/// the same in words: 1 "X+, Z+", 2 "X+, Z−", 3 "X−, Z−", 4 "X−, Z+",
/// 5 "Z+", 6 "X+", 7 "Z−", 8 "X−", 0 and 9 the centre):
///
/// ```text
///      +X
///       ^    2   6   1
///       |    7  0/9  5
///       |    3   8   4
///       +-----------------> +Z
/// ```
///
/// Derivation of the common ones. An outside (OD) turning tool cutting
/// toward the chuck (−Z) is touched off on the diameter with the lowest
/// point of its nose (centre − R in X) and on the end face with the point
/// nearest the chuck (centre − R in Z): its imaginary tip is at (−R, −R),
/// tip 3. A boring bar cutting toward the chuck touches the bore with the
/// top of its nose (centre + R in X) and the face likewise: (+R, −R),
/// tip 2. A tool set on the bottom of its nose only, its Z set to the nose
/// centre (a button or a neutral profiling tool turning an OD): (−R, 0),
/// tip 8. The diagonals 1 and 4 are 2 and 3 turned to face the chuck (back
/// turning, +Z); 5, 6 and 7 are the other three sides of the nose.
const FANUC: [(f64, f64); 10] = [
    (0.0, 0.0),   // 0: the nose centre is the programmed point
    (1.0, 1.0),   // 1: X+, Z+
    (1.0, -1.0),  // 2: X+, Z− (boring toward the chuck)
    (-1.0, -1.0), // 3: X−, Z− (OD turning toward the chuck)
    (-1.0, 1.0),  // 4: X−, Z+ (OD back turning)
    (0.0, 1.0),   // 5: Z+
    (1.0, 0.0),   // 6: X+
    (0.0, -1.0),  // 7: Z−
    (-1.0, 0.0),  // 8: X−
    (0.0, 0.0),   // 9: the nose centre, as 0
];

impl Nose {
    /// Whether the nose can be used: a finite radius ≥ 0 and a tip
    /// direction 0–9. The message says what is wrong, as the control's
    /// offset screen refuses it.
    pub fn check(&self) -> Result<(), String> {
        if self.tip > 9 {
            return Err(format!(
                "imaginary tip direction {}: a tip direction is 0 to 9 (1–8 round the nose, 0 and 9 the nose centre)",
                self.tip
            ));
        }
        if !(self.radius.is_finite() && self.radius >= 0.0) {
            return Err(format!("nose radius {}: a nose radius is a length of 0 or more", self.radius));
        }
        Ok(())
    }

    /// The imaginary tip's place from the nose centre, (X, Z) in mm, X a
    /// radius, the tip numbered as `numbers` says; (0, 0) for tip 0 and 9,
    /// and for a tip outside 0–9 (which [`Nose::check`] refuses).
    pub fn tip_vector(&self, numbers: TipNumbers) -> (f64, f64) {
        let (sx, sz) = FANUC.get(usize::from(numbers.fanuc_tip(self.tip))).copied().unwrap_or_default();
        (sx * self.radius, sz * self.radius)
    }

    /// The nose centre when the imaginary tip is at `tip`.
    pub fn centre(&self, tip: Axes, numbers: TipNumbers) -> Axes {
        shifted(tip, self.tip_vector(numbers), -1.0)
    }
}

/// `p` moved by `k` times the (X, Z) vector `v`.
pub(in crate::interp) fn shifted(p: Axes, v: (f64, f64), k: f64) -> Axes {
    Axes { x: p.x + k * v.0, z: p.z + k * v.1, ..p }
}

/// The path of the nose centre of each move's tool: the toolpath (the
/// imaginary tip's path, what the machine's axes follow) moved by minus
/// the tip vector of the tool that makes each move. A tool with no nose
/// in `noses` is a point: its moves are kept.
///
/// The part gets what the nose circle sweeps along this path.
pub fn nose_centre_path(path: &Toolpath, noses: &BTreeMap<u32, Nose>, numbers: TipNumbers) -> Toolpath {
    let mut out = path.clone();
    for m in &mut out.moves {
        let Some(nose) = noses.get(&m.tool) else { continue };
        let v = nose.tip_vector(numbers);
        m.start = shifted(m.start, v, -1.0);
        m.end = shifted(m.end, v, -1.0);
        if let MoveKind::Arc(arc) = &mut m.kind {
            arc.center[0] -= v.0;
            arc.center[2] -= v.1;
        }
    }
    out
}

/// Tool nose radius compensation: [`compensate_with_returns`] puts the nose
/// centre on the programmed contour offset by the nose radius; each move
/// made with compensation on then ends at that centre plus its tip vector
/// `tips[i]` (X, Z), where the machine puts the imaginary tip. Moves made
/// with compensation off stay on the programmed points, as the program is
/// written to the imaginary tip: the start-up move runs from the
/// programmed point to the first tip point, the cancel move back.
///
/// `returns` are the multiple repetitive cycles' returns to their start
/// points (ascending indices in `moves`), made with the offset cancelled;
/// `jumps` LinuxCNC's jumps of the tool centre (a G70's profile's end),
/// as [`compensate_with_returns`] takes them.
///
/// Returns the moves and, for each, the input move it comes from.
///
/// # Errors
/// As [`compensate_with_returns`]; and an arc as the start-up move of a tool
/// whose tip is off its centre (LinuxCNC's entry arc): its start is the
/// tip, its end and centre the centre's, which no arc joins.
pub(in crate::interp) fn compensate_nose(
    moves: &[Move],
    tags: &[Option<Comp>],
    tips: &[(f64, f64)],
    returns: &[usize],
    jumps: &[(usize, Axes)],
    rules: Rules,
) -> Result<(Vec<Move>, Vec<usize>), Error> {
    let (mut out, origin) = compensate_with_returns(moves, tags, returns, jumps, rules)?;
    if tips.iter().all(|&v| v == (0.0, 0.0)) {
        return Ok((out, origin));
    }
    // Each move starts where the one before it ends; the first where it
    // starts, the tip before compensation.
    let mut before = out.first().map(|m| m.start);
    for (m, &o) in out.iter_mut().zip(&origin) {
        let on = tags.get(o).copied().flatten().is_some();
        let v = if on { tips.get(o).copied().unwrap_or_default() } else { (0.0, 0.0) };
        m.end = shifted(m.end, v, 1.0);
        if let MoveKind::Arc(arc) = &mut m.kind {
            arc.center[0] += v.0;
            arc.center[2] += v.1;
        }
        if let Some(p) = before {
            // An arc keeps its radius only where its start moves as its
            // centre does.
            let own = shifted(m.start, v, 1.0);
            if matches!(m.kind, MoveKind::Arc(_)) && (p.x - own.x).hypot(p.z - own.z) > 1e-9 {
                let message = "kezuri does not model an arc as the start-up move of tool nose radius compensation \
                               with a tip direction off the nose centre: make the start-up move G0 or G1";
                return Err(Error::new(ErrorKind::Compensation, message).at(Place::Compensated(o)));
            }
            m.start = p;
        }
        before = Some(m.end);
    }
    Ok((out, origin))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nose(tip: u8) -> Nose {
        Nose { radius: 0.8, tip }
    }

    #[test]
    fn lathe_tip_vectors_follow_the_figure() {
        // OD tool (3): tip below and toward the chuck of the centre.
        assert_eq!(nose(3).tip_vector(TipNumbers::Fanuc), (-0.8, -0.8));
        // Boring bar (2): tip above the centre, toward the chuck.
        assert_eq!(nose(2).tip_vector(TipNumbers::Fanuc), (0.8, -0.8));
        assert_eq!(nose(8).tip_vector(TipNumbers::Fanuc), (-0.8, 0.0));
        assert_eq!(nose(6).tip_vector(TipNumbers::Fanuc), (0.8, 0.0));
        assert_eq!(nose(5).tip_vector(TipNumbers::Fanuc), (0.0, 0.8));
        assert_eq!(nose(7).tip_vector(TipNumbers::Fanuc), (0.0, -0.8));
        assert_eq!(nose(1).tip_vector(TipNumbers::Fanuc), (0.8, 0.8));
        assert_eq!(nose(4).tip_vector(TipNumbers::Fanuc), (-0.8, 0.8));
        for tip in [0, 9] {
            assert_eq!(nose(tip).tip_vector(TipNumbers::Fanuc), (0.0, 0.0));
        }
        // LinuxCNC's OD tool on a front tool post is its 2: X mirrored.
        assert_eq!(nose(2).tip_vector(TipNumbers::LinuxCnc), (-0.8, -0.8));
        assert_eq!(nose(8).tip_vector(TipNumbers::LinuxCnc), (0.8, 0.0));
    }

    #[test]
    fn lathe_linuxcnc_orientations_are_fanuc_tips_mirrored_in_x() {
        let fanuc: Vec<u8> = (0..=10).map(|q| TipNumbers::LinuxCnc.fanuc_tip(q)).collect();
        assert_eq!(fanuc, [0, 4, 3, 2, 1, 5, 8, 7, 6, 9, 10]);
        for q in 0..=9 {
            assert_eq!(TipNumbers::Fanuc.fanuc_tip(q), q);
            let (x, z) = nose(q).tip_vector(TipNumbers::LinuxCnc);
            assert_eq!((-x, z), nose(q).tip_vector(TipNumbers::Fanuc), "Q{q}");
        }
    }

    #[test]
    fn lathe_every_tip_lies_on_the_square_round_the_nose() {
        // Each imaginary tip is where an X line and a Z line tangent to the
        // nose meet, or one tangent point: at most R from the centre in
        // each axis, and R or R·√2 away.
        for tip in 1..=8 {
            let (x, z) = nose(tip).tip_vector(TipNumbers::Fanuc);
            let d = x.hypot(z);
            assert!((d - 0.8).abs() < 1e-12 || (d - 0.8 * 2f64.sqrt()).abs() < 1e-12, "tip {tip}");
        }
    }

    #[test]
    fn lathe_nose_check_refuses_what_a_control_refuses() {
        assert!(nose(9).check().is_ok());
        assert!(nose(10).check().unwrap_err().contains("0 to 9"));
        assert!(Nose { radius: -0.4, tip: 3 }.check().is_err());
        assert!(Nose { radius: f64::NAN, tip: 3 }.check().is_err());
    }

    #[test]
    fn lathe_centre_is_the_tip_less_its_vector() {
        let tip = Axes { x: 10.0, z: -5.0, ..Axes::ZERO };
        let c = nose(3).centre(tip, TipNumbers::Fanuc);
        assert_eq!((c.x, c.z), (10.8, -4.2));
    }
}
