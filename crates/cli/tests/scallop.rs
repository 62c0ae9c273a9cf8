//! `kezuri scallop` as a user runs it: the oval end mill paper's figures, JSON keys, exit codes.

mod common;
use common::kezuri;

fn json(args: &[&str]) -> serde_json::Value {
    let o = kezuri(args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).expect("one JSON object on stdout")
}

fn f(v: &serde_json::Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("{key} in {v}"))
}

#[test]
fn seed_001_pick_feed_control_through_the_command_line() {
    for (angle, paper) in [("0", 0.462), ("15", 0.484), ("60", 1.052)] {
        let v = json(&["scallop", "--tool", "oval:16,24", "--angle", angle, "--cusp", "0.010", "--json"]);
        assert!((f(&v, "pick_feed_mm") - paper).abs() <= 0.002, "{angle}°: {v}");
        assert!((f(&v, "cusp_mm") - 0.010).abs() < 1e-9, "{v}");
        assert_eq!(v["tool"], "oval:16,24");
        assert_eq!(f(&v, "angle_deg"), angle.parse::<f64>().unwrap());
        assert_eq!(v["target_mm"], 0.010);
    }
}

#[test]
fn seed_001_constant_pick_feed_through_the_command_line() {
    let at = |angle: &str| {
        let v = json(&["scallop", "--tool", "oval:16,24", "--angle", angle, "--pick-feed", "0.8", "--json"]);
        assert_eq!(f(&v, "pick_feed_mm"), 0.8);
        let up = f(&v, "step_up_cusp_mm");
        let down = f(&v, "step_down_cusp_mm");
        assert!((up - down).abs() < 1e-12 && (up - f(&v, "cusp_mm")).abs() < 1e-12, "{v}");
        assert!((f(&v, "plan_stepover_mm") - 0.8 * angle.parse::<f64>().unwrap().to_radians().cos()).abs() < 1e-12);
        f(&v, "cusp_mm") * 1e3
    };
    assert!((at("15") - 27.0).abs() < 0.5);
    assert!((at("60") - 6.0).abs() < 0.5);
}

#[test]
fn plain_text_names_the_pick_feed_the_cusp_and_both_steps() {
    let o = kezuri(&["scallop", "--tool", "ball:6", "--angle", "30", "--pick-feed", "0.5"]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    for want in ["pick feed", "cusp", "step-up", "step-down", "R - sqrt(R^2 - Pf^2/4)"] {
        assert!(text.contains(want), "{want}: {text}");
    }
    let help = kezuri(&["scallop", "--help"]);
    let help = String::from_utf8_lossy(&help.stdout);
    assert!(help.contains("Examples:") && help.contains("--cusp 0.010"), "{help}");
}

#[test]
fn bad_input_exits_1_with_a_reason() {
    for (args, why) in [
        (&["--tool", "oval:16,24", "--angle", "90", "--pick-feed", "1"][..], "angle"),
        (&["--tool", "oval:16,24", "--angle", "-5", "--pick-feed", "1"], "angle"),
        (&["--tool", "oval:16,24", "--angle", "NaN", "--pick-feed", "1"], "angle"),
        (&["--tool", "oval:16,24", "--angle", "30", "--pick-feed", "-1"], "--pick-feed"),
        (&["--tool", "oval:16,24", "--angle", "30", "--pick-feed", "NaN"], "--pick-feed"),
        (&["--tool", "oval:16,24", "--angle", "30", "--pick-feed", "40"], "uncut strip"),
        (&["--tool", "oval:16,24", "--angle", "30", "--cusp", "-0.01"], "--cusp"),
        (&["--tool", "oval:16,24", "--angle", "30", "--cusp", "NaN"], "cusp"),
        (&["--tool", "oval:16,24", "--angle", "30", "--cusp", "0"], "--cusp"),
        (&["--tool", "ball:-3", "--angle", "30", "--cusp", "0.01"], "the diameter must be a length"),
    ] {
        let mut all = vec!["scallop"];
        all.extend_from_slice(args);
        let o = kezuri(&all);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
        assert!(err.contains(why), "{args:?}: {err}");
        assert!(o.stdout.is_empty() && !err.contains("panicked"), "{args:?}");
    }
    // Neither --pick-feed nor --cusp, or both: a usage error.
    assert_eq!(kezuri(&["scallop", "--tool", "ball:6", "--angle", "30"]).status.code(), Some(2));
    let both = ["scallop", "--tool", "ball:6", "--angle", "30", "--pick-feed", "1", "--cusp", "0.01"];
    assert_eq!(kezuri(&both).status.code(), Some(2));
}

#[test]
fn a_loose_target_gives_the_widest_overlapping_pick_feed_with_a_note() {
    let o = kezuri(&["scallop", "--tool", "flat:6", "--angle", "0", "--cusp", "0.01", "--json"]);
    assert!(o.status.success());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(f(&v, "pick_feed_mm"), 6.0);
    assert_eq!(v["width_limited"], true);
    assert!(String::from_utf8_lossy(&o.stderr).contains("widest"));
}
