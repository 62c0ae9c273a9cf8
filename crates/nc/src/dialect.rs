//! The language a program is read in: which control's G-code.

use std::fmt;
use std::str::FromStr;

/// Which control a program is written for, as the parser and the
/// interpreter read it. How kezuri *writes* a program is
/// [`crate::write::Dialect`] and the posts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Dialect {
    /// Fanuc (ISO) with Custom Macro B: `O` numbers programs, `#1`–`#33`
    /// are a macro's arguments, an axis word without a decimal point counts
    /// least increments unless the settings say otherwise.
    #[default]
    Fanuc,
    /// Haas: Fanuc with Haas's codes (`G154 P`, `G187`, …).
    Haas,
    /// LinuxCNC (rs274ngc): `O` words are subroutines and control flow,
    /// named parameters `#<name>`, polar `@ ^`, whole units without a
    /// decimal point.
    LinuxCnc,
    /// GRBL 1.1: LinuxCNC's words without macros, subroutines or a tool changer.
    Grbl,
    /// A Fanuc lathe (T series): Fanuc's language with the lathe's codes (G
    /// code system A, B or C: [`crate::interp::Lathe`]), X a diameter, U W H
    /// incremental X Z C under system A, the turning cycles.
    FanucLathe,
    /// A Haas lathe: the Fanuc lathe's language with Haas's codes and the
    /// one-block forms of the turning cycles.
    HaasLathe,
}

impl Dialect {
    /// Every dialect, in the order of their names in the documentation.
    pub const ALL: [Dialect; 6] =
        [Dialect::Fanuc, Dialect::Haas, Dialect::LinuxCnc, Dialect::Grbl, Dialect::FanucLathe, Dialect::HaasLathe];

    /// The lower-case name: `fanuc`, `haas`, `linuxcnc`, `grbl`, `fanuc-lathe`
    /// or `haas-lathe`.
    pub fn name(self) -> &'static str {
        match self {
            Dialect::Fanuc => "fanuc",
            Dialect::Haas => "haas",
            Dialect::LinuxCnc => "linuxcnc",
            Dialect::Grbl => "grbl",
            Dialect::FanucLathe => "fanuc-lathe",
            Dialect::HaasLathe => "haas-lathe",
        }
    }

    /// Fanuc or Haas, mill or lathe: the Fanuc family (macro B, `O`
    /// program numbers).
    pub fn is_fanuc(self) -> bool {
        matches!(self, Dialect::Fanuc | Dialect::Haas | Dialect::FanucLathe | Dialect::HaasLathe)
    }

    /// Haas's codes, mill or lathe.
    pub fn is_haas(self) -> bool {
        matches!(self, Dialect::Haas | Dialect::HaasLathe)
    }

    /// A Fanuc or Haas lathe: X a diameter and the lathe's G codes from the
    /// start. (LinuxCNC turns with `G7`/`G18` in its own dialect.)
    pub fn is_lathe(self) -> bool {
        matches!(self, Dialect::FanucLathe | Dialect::HaasLathe)
    }
}

impl fmt::Display for Dialect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Dialect {
    type Err = String;

    fn from_str(s: &str) -> Result<Dialect, String> {
        Dialect::ALL
            .into_iter()
            .find(|d| d.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| format!("'{s}' is not a dialect: fanuc, haas, linuxcnc, grbl, fanuc-lathe or haas-lathe"))
    }
}

#[cfg(test)]
mod tests {
    use super::Dialect;

    #[test]
    fn names_read_back() {
        for d in Dialect::ALL {
            assert_eq!(d.name().parse::<Dialect>(), Ok(d));
        }
        assert_eq!("LinuxCNC".parse::<Dialect>(), Ok(Dialect::LinuxCnc));
        assert!("okuma"
            .parse::<Dialect>()
            .unwrap_err()
            .contains("fanuc, haas, linuxcnc, grbl, fanuc-lathe or haas-lathe"));
    }
}
