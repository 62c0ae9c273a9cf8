//! `kezuri engage` as a user runs it: the JSON the command-line contract
//! names, the sweep over inclinations, the pictures and the errors.

mod common;
use common::kezuri;

const PAPER: [&str; 12] = [
    "engage",
    "--tool",
    "oval:16,24",
    "--angle",
    "45",
    "--pick-feed",
    "0.8",
    "--depth",
    "0.8",
    "--feed-per-tooth",
    "0.16",
    "--json",
];

fn json(args: &[&str]) -> serde_json::Value {
    let o = kezuri(args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).expect("JSON on stdout")
}

fn numbers(v: &serde_json::Value, key: &str) -> Vec<f64> {
    let a = v[key].as_array().unwrap_or_else(|| panic!("{key} in {v}"));
    a.iter().map(|x| x.as_f64().unwrap_or_else(|| panic!("{key} holds {x}"))).collect()
}

fn f(v: &serde_json::Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("{key} in {v}"))
}

#[test]
fn one_case_prints_the_contracts_keys_over_a_revolution() {
    let v = json(&PAPER);
    let theta = numbers(&v, "angles_deg");
    assert_eq!(theta.len(), 360);
    let step: Vec<f64> = theta.windows(2).map(|w| w[1] - w[0]).collect();
    assert!(step.iter().all(|s| (s - 1.0).abs() < 1e-9), "one degree apart: {step:?}");
    let (area, lg, ed, torque) =
        (numbers(&v, "area_mm2"), numbers(&v, "lg_mm"), numbers(&v, "ed_mm3"), numbers(&v, "torque_n_mm"));
    for k in 0..360 {
        assert!(area[k] >= 0.0 && lg[k] >= 0.0);
        assert!((ed[k] - area[k] * lg[k]).abs() <= 1e-12 + 1e-9 * ed[k], "E_d = A·L_G at {}", theta[k]);
        assert!((torque[k] - 3500.0 * ed[k]).abs() <= 1e-9 * (1.0 + torque[k]));
        // Where there is no chip there is no distance either.
        if area[k] == 0.0 {
            assert_eq!(ed[k], 0.0);
        }
    }
    let area_max = area.iter().cloned().fold(0.0, f64::max);
    assert_eq!(f(&v, "area_max_mm2"), area_max);
    assert!(area_max > 0.01 && area_max < 1.0, "{area_max} mm²");
    assert_eq!(f(&v, "ed_max_mm3"), ed.iter().cloned().fold(0.0, f64::max));
    assert!((f(&v, "torque_max_n_mm") - 3500.0 * f(&v, "ed_max_mm3")).abs() < 1e-9 * f(&v, "torque_max_n_mm"));
    let engaged = numbers(&v, "engaged_deg");
    assert_eq!(engaged.len(), 2);
    assert!(engaged[0] < engaged[1] && engaged[1] - engaged[0] < 360.0, "{engaged:?}");
    for k in 0..360 {
        let inside = theta[k] >= engaged[0] - 1e-9 && theta[k] <= engaged[1] + 1e-9;
        assert_eq!(area[k] > 0.0, inside, "θ {} against the engaged range {engaged:?}", theta[k]);
    }
    assert!(f(&v, "chip_volume_mm3") > 0.0);
    assert_eq!(f(&v, "pick_feed_mm"), 0.8);
    assert_eq!(v["tool"], "oval:16,24");
}

#[test]
fn with_a_straight_flute_e_d_over_a_revolution_is_the_chip_volume() {
    let mut args = PAPER.to_vec();
    args.extend(["--helix", "0", "--steps", "3600"]);
    let v = json(&args);
    // E_d(θ) dθ over one revolution, θ in radians: the trapezoid rule on a
    // periodic function that is zero outside the engaged range.
    let ed = numbers(&v, "ed_mm3");
    let integral: f64 = ed.iter().sum::<f64>() * std::f64::consts::TAU / ed.len() as f64;
    let volume = f(&v, "chip_volume_mm3");
    assert!((integral - volume).abs() < 2e-3 * volume, "∫E_d dθ {integral} against the volume {volume}");
}

#[test]
fn a_sweep_gives_a_case_per_inclination_step_and_cut_and_the_pictures() {
    let dir = tempfile::tempdir().unwrap();
    let at = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    let (png, svg, csv) = (at("e.png"), at("e.svg"), at("e.csv"));
    let v = json(&[
        "engage",
        "--tool",
        "oval:16,24",
        "--angle",
        "0:75:15",
        "--pick-feed",
        "auto",
        "--cusp",
        "0.01",
        "--depth",
        "0.8",
        "--feed-per-tooth",
        "0.16",
        "--step",
        "both",
        "--cut",
        "both",
        "--steps",
        "90",
        "--json",
        "--png",
        &png,
        "--svg",
        &svg,
        "--csv",
        &csv,
    ]);
    let cases = v["cases"].as_array().expect("cases");
    assert_eq!(cases.len(), 6 * 4);
    // The pick feeds for a 10 µm cusp: as `kezuri scallop --cusp 0.01` finds them.
    let at_75 = cases.iter().find(|c| c["inclination_deg"] == 75.0).unwrap();
    assert!((f(at_75, "pick_feed_mm") - 1.739).abs() < 0.001, "{}", at_75["pick_feed_mm"]);
    for c in cases {
        assert_eq!(numbers(c, "angles_deg").len(), 90);
    }
    let picture = image::open(&png).expect("a PNG").to_rgba8();
    assert!(picture.width() > 600 && picture.height() > 4 * 400, "{:?}", picture.dimensions());
    let svg = std::fs::read_to_string(&svg).unwrap();
    // Each chart's title names the tool.
    for title in [
        "Chip area per rotation angle (oval:16,24, step-up, down-cut)",
        "Largest chip area per inclination, oval:16,24",
        "Largest E_d per inclination, oval:16,24",
    ] {
        assert!(svg.contains(title), "{title}");
    }
    let csv = std::fs::read_to_string(&csv).unwrap();
    assert!(csv.starts_with("angle_deg,step,cut,pick_feed_mm,theta_deg,area_mm2,lg_mm,ed_mm3,torque_n_mm\n"));
    assert_eq!(csv.lines().count(), 1 + 24 * 90);
}

#[test]
fn bad_input_is_a_clear_error() {
    let with = |option: &str, value: &str| {
        let mut args: Vec<&str> = PAPER.to_vec();
        match args.iter().position(|w| *w == option) {
            Some(k) => args[k + 1] = value,
            None => args.extend([option, value]),
        }
        let o = kezuri(&args);
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(!o.status.success() && !err.contains("panicked"), "{option} {value}: {err}");
        assert!(o.stdout.is_empty(), "{option} {value}: nothing on stdout");
        err
    };
    assert!(with("--angle", "90").contains("--angle"));
    assert!(with("--angle", "0:75:0").contains("STEP"));
    assert!(with("--helix", "90").contains("--helix"));
    assert!(with("--pick-feed", "25").contains("wider than the cutter"), "25 mm at 45° is 17.7 mm in plan");
    assert!(with("--pick-feed", "0.4,0.5").contains("one per angle"));
    assert!(with("--depth", "0").contains("--depth"));
    assert!(with("--depth", "60").contains("flutes"), "the chip would rise above the flutes");
    assert!(with("--flutes", "0").contains("--flutes"));
    assert!(with("--feed-per-tooth", "-1").contains("--feed-per-tooth"));
    assert!(with("--tool", "oval:16").contains("oval"));
}

#[test]
fn a_cusp_as_tall_as_the_stock_is_warned_of() {
    let mut args = PAPER.to_vec();
    args[6] = "auto";
    args.extend(["--cusp", "100"]);
    let o = kezuri(&args);
    assert!(o.status.success());
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("leave stock between them uncut"), "{e}");
    let o = kezuri(&PAPER);
    assert!(!String::from_utf8_lossy(&o.stderr).contains("warning"), "a 0.8 mm pick feed at 45° cuts it all");
}

#[test]
fn the_tools_torque_is_every_flutes_together() {
    // Side milling 8 mm of a 10 mm flat end mill: a tooth cuts over 147°,
    // so with four flutes (90° apart) two cut at once.
    let base = [
        "engage",
        "--tool",
        "flat:10",
        "--angle",
        "0",
        "--pick-feed",
        "8",
        "--depth",
        "3",
        "--feed-per-tooth",
        "0.1",
        "--json",
    ];
    let with = |flutes: &str| {
        let mut args = base.to_vec();
        args.extend(["--flutes", flutes]);
        json(&args)
    };
    let one = with("1");
    assert_eq!(numbers(&one, "tool_torque_n_mm"), numbers(&one, "torque_n_mm"));
    let four = with("4");
    let (tooth, tool) = (numbers(&four, "torque_n_mm"), numbers(&four, "tool_torque_n_mm"));
    for k in 0..360 {
        let sum: f64 = (0..4).map(|j| tooth[(k + 360 - 90 * j) % 360]).sum();
        assert!((tool[k] - sum).abs() <= 1e-9 * (1.0 + sum), "θ {k}°: {} vs {sum}", tool[k]);
    }
    assert!(f(&four, "tool_torque_max_n_mm") > 1.2 * f(&four, "torque_max_n_mm"));
}
