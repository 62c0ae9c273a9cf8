//! `kezuri view`'s pages in a real browser: headless Chromium (WebGL2 on
//! SwiftShader) driven by `tests/browser/check.mjs` (playwright-core): the
//! first frame, the path's colours where the projection puts them, the
//! slider, a click on a segment and on a line, the hostile text shown as
//! text, no console errors. Needs `chromium`, `node` and the test's npm
//! packages (`npm ci` in tests/browser), which `.ci/run` installs; without
//! them the test says so and passes, unless KEZURI_REQUIRE_BROWSER=1.

mod common;

use std::path::Path;
use std::process::Command;

use common::{kezuri, ok, path};

/// Why the browser test cannot run here, if it cannot.
fn missing() -> Option<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/browser");
    let found = |program: &str| Command::new(program).arg("--version").output().is_ok_and(|o| o.status.success());
    if !found("node") {
        return Some("node is not installed".into());
    }
    if !Path::new("/usr/bin/chromium").exists() {
        return Some("chromium is not installed (apt-get install chromium)".into());
    }
    if !dir.join("node_modules/playwright-core").exists() {
        return Some(format!("playwright-core is not installed: npm ci in {}", dir.display()));
    }
    None
}

#[test]
fn the_pages_work_in_chromium() {
    if let Some(why) = missing() {
        assert!(std::env::var("KEZURI_REQUIRE_BROWSER").is_err(), "KEZURI_REQUIRE_BROWSER is set, but {why}");
        eprintln!("SKIPPED: the view pages are not opened in a browser: {why}");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let samples = concat!(env!("CARGO_MANIFEST_DIR"), "/../../samples");
    let page = |name: &str| path(dir.path(), name);
    // The path alone; a simulated part with its deviation, a gouge and a
    // rapid into the stock; two tools from a relief with roughing; a
    // rotary program; arcs in all three planes, in inches.
    ok(&kezuri(&["view", &format!("{samples}/nameplate-cam.nc"), "--tool", "ball:6", "-o", &page("plate.html")]));
    let groove = page("groove.nc");
    std::fs::write(
        &groove,
        "G21 G90\nG0 X-5. Y5. Z5.\nG1 Z-1. F100.\nG1 X25. F300.\nG0 Y1. Z-0.2\nG0 X-5.\nG0 Z5.\nM30\n",
    )
    .unwrap();
    let target = page("flat.xyz");
    let grid: String = (0..=10).flat_map(|j| (0..=20).map(move |i| format!("{i} {j} -0.5\n"))).collect();
    std::fs::write(&target, grid).unwrap();
    ok(&kezuri(&[
        "view",
        &groove,
        "--sim",
        "--tool",
        "ball:6",
        "--res",
        "0.1",
        "--stock",
        "0,0,20,10,0",
        "--compare",
        &target,
        "-o",
        &page("groove.html"),
    ]));
    ok(&kezuri(&[
        "relief",
        &format!("{samples}/plum-sketch.png"),
        "--width",
        "40",
        "--depth",
        "2",
        "--tool",
        "ball:2",
        "--stepover",
        "1",
        "--rough",
        "flat:6",
        "--step-down",
        "1",
        "-o",
        &page("plum.nc"),
        "--view",
        &page("plum.html"),
    ]));
    // The relief's program read back, with the sample router's tool
    // lengths: it starts and ends with G91 G28 returns, which the page does
    // not place (the tool was drawn at X0 Y0 Z0 in the part before).
    ok(&kezuri(&[
        "view",
        &page("plum.nc"),
        "--machine",
        &format!("{samples}/tools/mill.toml"),
        "-o",
        &page("returns.html"),
    ]));
    ok(&kezuri(&["view", &format!("{samples}/o2007-thermal.nc"), "-o", &page("o2007.html")]));
    let arcs = page("arcs.nc");
    std::fs::write(
        &arcs,
        "G20 G90 G17\nG0 X0. Y0. Z0.2\nG1 Z-0.05 F10.\nG2 X1. Y0. I0.5 J0.\nG18 G3 X2. Z-0.05 I0.5 K0.\n\
         G19 G2 Y1. Z-0.05 J0.5 K0.\nG17 G3 X2. Y1. Z-0.2 I-0.5 J0.\nG0 Z0.2\nM30\n",
    )
    .unwrap();
    ok(&kezuri(&["view", &arcs, "--tool", "flat:3", "-o", &page("arcs.html")]));

    let shots = std::env::var("KEZURI_VIEW_SHOTS").unwrap_or_else(|_| path(dir.path(), "shots"));
    let pages: Vec<String> =
        ["plate", "groove", "plum", "returns", "o2007", "arcs"].iter().map(|p| page(&format!("{p}.html"))).collect();
    let o = Command::new("node")
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/browser"))
        .arg("check.mjs")
        .args(&pages)
        .args(["--out", &shots])
        .output()
        .expect("node runs");
    let report = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "check.mjs failed:\n{report}\n{}", String::from_utf8_lossy(&o.stderr));
    eprintln!("{report}");
}
