//! Input no chip can be computed from: the errors of
//! [`Chip::new`](super::Chip::new). Angles are held in radians and shown in
//! degrees.

use crate::error::{Error, ErrorKind};

/// No flutes.
pub(super) fn flutes() -> Error {
    Error::new(ErrorKind::Flutes, "the cutter must have at least 1 flute, got 0")
}

/// The helix angle is not in `[0, 90°)`.
pub(super) fn helix(h: f64) -> Error {
    Error::new(
        ErrorKind::Helix,
        format!("the helix angle must be from 0 up to (not including) 90 degrees, got {}", h.to_degrees()),
    )
}

/// The plane's angle α is not in `[0, 90°)`.
pub(super) fn angle(a: f64) -> Error {
    Error::new(
        ErrorKind::Angle,
        format!("the plane's angle must be from 0 up to (not including) 90 degrees, got {}", a.to_degrees()),
    )
}

/// The depth of cut `R_d` is not a positive number.
pub(super) fn depth(d: f64) -> Error {
    Error::new(ErrorKind::Depth, format!("the depth of cut must be a number > 0 mm, got {d}"))
}

/// The pick feed `P_f` is not a positive number.
pub(super) fn pick_feed(p: f64) -> Error {
    Error::new(ErrorKind::PickFeed, format!("the pick feed must be a number > 0 mm, got {p}"))
}

/// The passes do not overlap: `P_f·cos α` is wider than the cutter;
/// `widest` is `2R / cos α`.
pub(super) fn pick_feed_too_wide(pick_feed: f64, widest: f64) -> Error {
    Error::new(
        ErrorKind::NoOverlap,
        format!(
            "a pick feed of {pick_feed} mm is wider than the cutter: the passes would leave an uncut strip; \
             the widest that overlaps at this angle is {widest:.6} mm (the diameter / cos angle)"
        ),
    )
}

/// The feed per tooth `S_z` is not a number of at least
/// [`MIN_FEED_PER_TOOTH`](super::MIN_FEED_PER_TOOTH).
pub(super) fn feed_per_tooth(s: f64) -> Error {
    Error::new(
        ErrorKind::FeedPerTooth,
        format!("the feed per tooth must be a number of at least {} mm, got {s}", super::MIN_FEED_PER_TOOTH),
    )
}

/// The feed per tooth is at least the diameter: the teeth's cuts do not
/// overlap and there is no chip of the kind modelled.
pub(super) fn feed_per_tooth_too_wide(feed_per_tooth: f64, diameter: f64) -> Error {
    Error::new(
        ErrorKind::FeedPerToothTooWide,
        format!(
            "a feed per tooth of {feed_per_tooth} mm is not less than the cutter's diameter {diameter} mm: \
             the teeth's cuts would not overlap"
        ),
    )
}

/// The chip rises `needed` mm above the tip, above the flutes at `flutes`
/// mm: the stock plane reaches higher on the cutter than its cutting edge
/// (the profile and one diameter of cylinder above it).
pub(super) fn reach(needed: f64, flutes: f64) -> Error {
    Error::new(
        ErrorKind::Reach,
        format!(
            "the cutter cannot reach the depth: the chip rises {needed:.4} mm above the tip, \
             above the top of its flutes at {flutes:.4} mm (the profile and one diameter of cylinder)"
        ),
    )
}

/// No material is removed (the depth is below the resolution).
pub(super) fn no_chip() -> Error {
    Error::new(ErrorKind::NoChip, "no material is removed: the depth of cut is below the resolution")
}
