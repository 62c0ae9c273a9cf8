//! The single cycles of a Fanuc lathe: outer/inner diameter cutting (`G90`
//! in G code system A, `G77` in B, `G20` in C), threading (`G92`, `G78`,
//! `G21`) and end face cutting (`G94`, `G79`, `G24`), straight or with the
//! taper `R` (FANUC Series 0i-TF Plus Operator's Manual (B-64604EN), lathe
//! system, "Canned cycle" / "Single cycle": G90, G92, G94). Haas writes the
//! taper as `I` (G90, G92) and `K` (G94) (Haas Lathe Operator's Manual,
//! G-codes chapter).
//!
//! Each cycle is four moves from its start point A back to A. Positions are
//! the tool's: X a radius.

/// What a move of a turning cycle is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum StepKind {
    /// At rapid rate.
    Rapid,
    /// At the cutting feed.
    Feed,
    /// Threading: the feed synchronised with the spindle, one lead a turn.
    Thread,
}

/// One move of a turning cycle, to (`x`, `z`): X the radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Step {
    pub(crate) kind: StepKind,
    pub(crate) x: f64,
    pub(crate) z: f64,
}

impl Step {
    pub(crate) fn rapid(x: f64, z: f64) -> Step {
        Step { kind: StepKind::Rapid, x, z }
    }
    pub(crate) fn feed(x: f64, z: f64) -> Step {
        Step { kind: StepKind::Feed, x, z }
    }
    pub(crate) fn thread(x: f64, z: f64) -> Step {
        Step { kind: StepKind::Thread, x, z }
    }
}

/// Which single cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SingleCycle {
    /// Outer/inner diameter cutting: A system `G90`, B `G77`, C `G20`.
    Turning,
    /// Threading: `G92`, `G78`, `G21`.
    Threading,
    /// End face cutting: `G94`, `G79`, `G24`.
    Facing,
}

impl SingleCycle {
    /// Its G number in G code system `system` (`0` A, `1` B, `2` C).
    pub fn number(self, system: super::GCodeSystem) -> u32 {
        use super::GCodeSystem::*;
        match (self, system) {
            (SingleCycle::Turning, A) => 90,
            (SingleCycle::Turning, B) => 77,
            (SingleCycle::Turning, C) => 20,
            (SingleCycle::Threading, A) => 92,
            (SingleCycle::Threading, B) => 78,
            (SingleCycle::Threading, C) => 21,
            (SingleCycle::Facing, A) => 94,
            (SingleCycle::Facing, B) => 79,
            (SingleCycle::Facing, C) => 24,
        }
    }
}

/// A cycle's geometry that the program cannot have meant: the word to
/// blame (its letter) and what is wrong.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Refusal {
    pub(crate) letter: Option<u8>,
    pub(crate) message: String,
}

impl Refusal {
    pub(crate) fn at(letter: u8, message: impl Into<String>) -> Refusal {
        Refusal { letter: Some(letter), message: message.into() }
    }
    pub(crate) fn block(message: impl Into<String>) -> Refusal {
        Refusal { letter: None, message: message.into() }
    }
}

/// The moves of one single cycle from the start point (`x0`, `z0`) to the
/// end point (`x`, `z`) (radius, mm) with the taper `taper` (the manual's
/// R: the radius, for G94 the Z, where the cut starts less that of the end
/// point; 0 for a straight cut).
///
/// - Turning (G90): rapid in X to `x + taper`, feed to (`x`, `z`), feed out
///   in X to `x0`, rapid back in Z to `z0`.
/// - Threading (G92): the same, the cut threaded and the way out in X at
///   rapid rate.
/// - Facing (G94): rapid in Z to `z + taper`, feed to (`x`, `z`), feed out
///   in Z to `z0`, rapid back in X to `x0`.
///
/// The taper's sign follows the manual's four figures: where R and U/2
/// (W for G94) have opposite signs, |R| ≤ |U/2| (|W|), or the cut would
/// begin beyond the start point.
pub(crate) fn single_pass(
    cycle: SingleCycle,
    (x0, z0): (f64, f64),
    (x, z): (f64, f64),
    taper: f64,
) -> Result<[Step; 4], Refusal> {
    // The move the taper is measured along: X for G90/G92, Z for G94.
    let along = if cycle == SingleCycle::Facing { z - z0 } else { x - x0 };
    if taper * along < 0.0 && taper.abs() > along.abs() + 1e-9 {
        let (letter, half) = if cycle == SingleCycle::Facing { ('W', "W") } else { ('U', "U/2") };
        return Err(Refusal::at(
            b'R',
            format!(
                "the taper R{taper} is larger than the cycle's depth ({half} = {along}) with the opposite sign: \
                 the cut would begin beyond the start point (the manual allows |R| ≤ |{half}| there; {letter} \
                 is the end point less the start point)"
            ),
        ));
    }
    Ok(match cycle {
        SingleCycle::Turning => {
            [Step::rapid(x + taper, z0), Step::feed(x, z), Step::feed(x0, z), Step::rapid(x0, z0)]
        }
        SingleCycle::Threading => {
            [Step::rapid(x + taper, z0), Step::thread(x, z), Step::rapid(x0, z), Step::rapid(x0, z0)]
        }
        SingleCycle::Facing => {
            [Step::rapid(x0, z + taper), Step::feed(x, z), Step::feed(x, z0), Step::rapid(x0, z0)]
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straight_turning_is_four_moves_back_to_the_start() {
        // From (30, 2) to X radius 20, Z -40: in, along, out, back.
        let s = single_pass(SingleCycle::Turning, (30.0, 2.0), (20.0, -40.0), 0.0).unwrap();
        assert_eq!(s, [Step::rapid(20.0, 2.0), Step::feed(20.0, -40.0), Step::feed(30.0, -40.0), Step::rapid(30.0, 2.0)]);
    }

    #[test]
    fn taper_starts_the_cut_r_from_the_end_radius() {
        // OD taper toward the chuck: U < 0, W < 0, R < 0 (the manual's
        // first figure): the cut starts at radius 20 - 3 = 17.
        let s = single_pass(SingleCycle::Turning, (30.0, 2.0), (20.0, -40.0), -3.0).unwrap();
        assert_eq!(s[0], Step::rapid(17.0, 2.0));
        assert_eq!(s[1], Step::feed(20.0, -40.0));
        // The third figure: U < 0, R > 0, |R| <= |U/2|.
        assert!(single_pass(SingleCycle::Turning, (30.0, 2.0), (20.0, -40.0), 10.0).is_ok());
        let e = single_pass(SingleCycle::Turning, (30.0, 2.0), (20.0, -40.0), 10.5).unwrap_err();
        assert_eq!(e.letter, Some(b'R'));
    }

    #[test]
    fn facing_tapers_in_z() {
        let s = single_pass(SingleCycle::Facing, (30.0, 2.0), (5.0, -3.0), -1.5).unwrap();
        assert_eq!(s, [Step::rapid(30.0, -4.5), Step::feed(5.0, -3.0), Step::feed(5.0, 2.0), Step::rapid(30.0, 2.0)]);
    }

    #[test]
    fn threading_leaves_at_rapid() {
        let s = single_pass(SingleCycle::Threading, (15.0, 5.0), (9.0, -30.0), 0.0).unwrap();
        assert_eq!(s[1].kind, StepKind::Thread);
        assert_eq!(s[2], Step::rapid(15.0, -30.0));
    }
}
