//! What the tests of a Fanuc or Haas lathe's programs share: the lathe's
//! settings and a program's run, its toolpath or its error.

use kezuri_geom::{Axes, Toolpath};
use kezuri_nc::interp::{Control, CoordSettings, GCodeSystem, IntegerInput, Lathe, Outcome, Settings, XMode};
use kezuri_nc::Dialect;

/// A Fanuc lathe in G code `system`: X a diameter, an axis word without a
/// decimal point in least increments (as the control leaves the factory),
/// the reference position at X100 (radius) Z200 and known on every axis.
pub fn lathe(system: GCodeSystem) -> Settings {
    Settings {
        dialect: Dialect::FanucLathe,
        integer_input: IntegerInput::Increments,
        coords: CoordSettings { control: Control::Fanuc, ..CoordSettings::default() },
        home: Axes { x: 100.0, z: 200.0, ..Axes::ZERO },
        reference_given: [true; 4],
        lathe: Some(Lathe { x: XMode::Diameter, system }),
        ..Settings::default()
    }
}

/// A Fanuc lathe in G code system A, the default.
pub fn fanuc() -> Settings {
    lathe(GCodeSystem::A)
}

/// A Haas lathe: the Fanuc lathe's settings with Haas's dialect and control.
pub fn haas() -> Settings {
    Settings {
        dialect: Dialect::HaasLathe,
        coords: CoordSettings { control: Control::Haas, ..CoordSettings::default() },
        lathe: None,
        ..fanuc()
    }
}

/// The outcome of `text` (file `t.nc`), which must run to its end.
pub fn outcome(text: &str, settings: &Settings) -> Outcome {
    super::run("t.nc", text, settings).completed()
}

/// The toolpath of `text` (file `t.nc`), which must run to its end.
pub fn path(text: &str, settings: &Settings) -> Toolpath {
    outcome(text, settings).toolpath
}

/// The message of the error that stops `text`, and the text its span covers.
pub fn error(text: &str, settings: &Settings) -> (String, String) {
    let ran = super::run("t.nc", text, settings);
    let d = ran.error().unwrap_or_else(|| panic!("no error:\n{text}")).clone();
    (d.message.clone(), text[d.span.start as usize..d.span.end as usize].to_string())
}
