//! docs/view.md's way to open a page headless works as written: its
//! `chromium --headless … --dump-dom` command, run on a page, finds the
//! page drawn (`data-ready="1"`). Without Chromium it says so and passes.

mod common;
use common::{kezuri, ok, path};

/// The shell commands of docs/view.md's section "Opening a page headless"
/// that start Chromium, `\` continuations joined.
fn headless_commands() -> Vec<String> {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/view.md")).unwrap();
    let section =
        doc.split("## Opening a page headless").nth(1).expect("docs/view.md says how to open a page headless");
    let section = section.split("\n## ").next().unwrap();
    let mut out = Vec::new();
    let mut pending = String::new();
    for line in section.lines() {
        if let Some(start) = line.trim_end().strip_suffix('\\') {
            pending.push_str(start);
            continue;
        }
        pending.push_str(line);
        let command = std::mem::take(&mut pending);
        if command.trim_start().starts_with("chromium ") {
            out.push(command.trim().to_string());
        }
    }
    out
}

#[test]
fn docs_view_opens_a_page_headless() {
    let commands = headless_commands();
    assert_eq!(commands.len(), 2, "a screenshot and a check: {commands:?}");
    for c in &commands {
        for flag in ["--headless", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"] {
            assert!(c.contains(flag), "{c}: without {flag}");
        }
    }
    let chromium = std::env::var("KEZURI_CHROMIUM").unwrap_or_else(|_| "/usr/bin/chromium".into());
    if !std::path::Path::new(&chromium).exists() {
        eprintln!("skipped: no Chromium at {chromium}");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let samples = concat!(env!("CARGO_MANIFEST_DIR"), "/../../samples");
    let html = path(dir.path(), "plate.html");
    ok(&kezuri(&[
        "view",
        &format!("{samples}/nameplate-cam.nc"),
        "--sim",
        "--tool",
        "ball:6",
        "--res",
        "0.5",
        "-o",
        &html,
    ]));
    let check = commands.iter().find(|c| c.contains("--dump-dom")).expect("a --dump-dom check");
    let check = check.replacen("chromium ", &format!("{chromium} "), 1);
    let o = std::process::Command::new("sh").arg("-c").arg(&check).current_dir(dir.path()).output().unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains(r#"data-ready="1""#), "{check}:\n{out}\n{}", String::from_utf8_lossy(&o.stderr));

    // The picture shows the part: light pixels over much of the 3D view
    // (left of the program text, below the toolbar), not the tool alone.
    let shot = commands.iter().find(|c| c.contains("--screenshot")).expect("a --screenshot picture");
    let shot = shot.replacen("chromium ", &format!("{chromium} "), 1);
    // The shot is taken at the page's load, the drawing just after: on a
    // busy machine (the whole suite running) it may come first, and the doc
    // says to take it again. Up to five tries, a pause between.
    let light_pixels = || {
        let o = std::process::Command::new("sh").arg("-c").arg(&shot).current_dir(dir.path()).output().unwrap();
        let png = dir.path().join("plate.png");
        let picture = image::open(&png)
            .unwrap_or_else(|e| panic!("{shot}: {e}\n{}", String::from_utf8_lossy(&o.stderr)))
            .to_luma8();
        assert_eq!(picture.dimensions(), (1280, 800));
        let view = (0..900u32).flat_map(|x| (50..750u32).map(move |y| (x, y)));
        view.filter(|&(x, y)| picture.get_pixel(x, y).0[0] > 100).count()
    };
    let drawn = 900 * 700 / 20;
    let mut tries = Vec::new();
    while tries.len() < 5 && tries.last().is_none_or(|&n| n <= drawn) {
        if !tries.is_empty() {
            std::thread::sleep(std::time::Duration::from_secs(2));
        }
        tries.push(light_pixels());
    }
    assert!(tries.iter().any(|&n| n > drawn), "{shot}: light pixels in the view, try by try: {tries:?}");
}
