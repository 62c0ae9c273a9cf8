//! Work offsets as the controls number them: G54 … G59 first, then the
//! additional ones (Fanuc's G54.1 P, Haas' G154 P, LinuxCNC's G59.1 …),
//! which the interpreter reads and the writer gives back.

/// Index of the first additional work offset (G54.1 P1, G154 P1, G110,
/// G59.1) after G54 … G59.
pub const EXTRA_OFFSETS: usize = 6;

/// How many additional work offsets there are (Haas G154 P1–P99).
pub const EXTRA_OFFSET_COUNT: usize = 99;
