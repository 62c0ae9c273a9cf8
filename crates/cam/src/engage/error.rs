//! Input no chip can be computed from.

use std::fmt;

/// Why [`Chip::new`](super::Chip::new) refused an [`Engagement`](super::Engagement).
/// Angles are held in radians and shown in degrees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EngageError {
    /// No flutes.
    Flutes,
    /// The helix angle is not in `[0, 90°)`.
    Helix(f64),
    /// The plane's angle α is not in `[0, 90°)`.
    Angle(f64),
    /// The depth of cut `R_d` is not a positive number.
    Depth(f64),
    /// The pick feed `P_f` is not a positive number.
    PickFeed(f64),
    /// The passes do not overlap: `P_f·cos α` is wider than the cutter.
    PickFeedTooWide {
        /// The pick feed asked for, mm.
        pick_feed: f64,
        /// The widest that overlaps, `2R / cos α`, mm.
        widest: f64,
    },
    /// The feed per tooth `S_z` is not a number of at least
    /// [`MIN_FEED_PER_TOOTH`](super::MIN_FEED_PER_TOOTH).
    FeedPerTooth(f64),
    /// The feed per tooth is at least the diameter: the teeth's cuts do not
    /// overlap and there is no chip of the kind modelled.
    FeedPerToothTooWide {
        /// The feed per tooth asked for, mm.
        feed_per_tooth: f64,
        /// The cutter's diameter, mm.
        diameter: f64,
    },
    /// The chip rises above the flutes: the stock plane reaches higher on
    /// the cutter than its cutting edge (the profile and one diameter of
    /// cylinder above it).
    Reach {
        /// Height of the chip's top above the tip, mm.
        needed: f64,
        /// Height of the top of the flutes above the tip, mm.
        flutes: f64,
    },
    /// No material is removed (the depth is below the resolution).
    NoChip,
}

impl fmt::Display for EngageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            EngageError::Flutes => f.write_str("the cutter must have at least 1 flute, got 0"),
            EngageError::Helix(h) => {
                write!(f, "the helix angle must be from 0 up to (not including) 90 degrees, got {}", h.to_degrees())
            }
            EngageError::Angle(a) => {
                write!(f, "the plane's angle must be from 0 up to (not including) 90 degrees, got {}", a.to_degrees())
            }
            EngageError::Depth(d) => write!(f, "the depth of cut must be a number > 0 mm, got {d}"),
            EngageError::PickFeed(p) => write!(f, "the pick feed must be a number > 0 mm, got {p}"),
            EngageError::PickFeedTooWide { pick_feed, widest } => write!(
                f,
                "a pick feed of {pick_feed} mm is wider than the cutter: the passes would leave an uncut strip; \
                 the widest that overlaps at this angle is {widest:.6} mm (the diameter / cos angle)"
            ),
            EngageError::FeedPerTooth(s) => {
                write!(f, "the feed per tooth must be a number of at least {} mm, got {s}", super::MIN_FEED_PER_TOOTH)
            }
            EngageError::FeedPerToothTooWide { feed_per_tooth, diameter } => write!(
                f,
                "a feed per tooth of {feed_per_tooth} mm is not less than the cutter's diameter {diameter} mm: \
                 the teeth's cuts would not overlap"
            ),
            EngageError::Reach { needed, flutes } => write!(
                f,
                "the cutter cannot reach the depth: the chip rises {needed:.4} mm above the tip, \
                 above the top of its flutes at {flutes:.4} mm (the profile and one diameter of cylinder)"
            ),
            EngageError::NoChip => f.write_str("no material is removed: the depth of cut is below the resolution"),
        }
    }
}

impl std::error::Error for EngageError {}
