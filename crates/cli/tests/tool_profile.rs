//! `kezuri tool profile` on 16-bit PNG pictures of a known tool, and
//! `kezuri wear apply` with the profile it writes.

use std::path::Path;

use kezuri_correct::synthetic::View;
use kezuri_correct::tool_image::GrayImage;
use kezuri_geom::{SplitMix64, ToolProfile};

mod common;
use common::{kezuri, ok, path};

const PIXEL: f64 = 0.00071;
const R: f64 = 0.15;

/// A 0.3 mm ball end mill, 2 µm of its tip worn back, 8 µm runout.
fn view(axis_x: f64, tip_y: f64) -> View {
    let z: Vec<f64> = (0..=600).map(|k| 0.002 + 0.3 * k as f64 / 600.0).collect();
    let r = z.iter().map(|&z| if z < R { (z * (2.0 * R - z)).sqrt() } else { R }).collect();
    View {
        edges: ToolProfile::new(z, r).unwrap(),
        runout_mm: 0.008,
        web: 0.8,
        pixel_mm: PIXEL,
        axis_x,
        tip_y,
        levels: (0.1, 0.9),
        noise: 0.01,
    }
}

fn save(img: &GrayImage, file: &Path) {
    let v: Vec<u16> = img.pixels.iter().map(|&p| (p * 65535.0).round() as u16).collect();
    image::ImageBuffer::<image::Luma<u16>, _>::from_raw(img.width as u32, img.height as u32, v)
        .unwrap()
        .save(file)
        .unwrap();
}

fn json(args: &[&str]) -> serde_json::Value {
    serde_json::from_str(&ok(&kezuri(args))).expect("one JSON object")
}

#[test]
fn one_field_of_png_frames_gives_profile_runout_and_wear() {
    let dir = tempfile::tempdir().unwrap();
    let v = view(240.0, 300.0);
    let mut rng = SplitMix64::new(5);
    let mut args = vec!["tool".to_string(), "profile".to_string()];
    for (k, f) in v.frames(24, 480, 330, [0.0, 0.0], &mut rng).iter().enumerate() {
        let name = path(dir.path(), &format!("f{k:03}.png"));
        save(f, Path::new(&name));
        args.push(name);
    }
    let csv = path(dir.path(), "t.csv");
    let png = path(dir.path(), "t.png");
    args.extend(
        ["--pixel-um", "0.71", "--tip-row", "300", "--nominal", "ball:0.3", "-o", &csv, "--png", &png, "--json"]
            .map(String::from),
    );
    let out = json(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(out["frames"], 24);
    let runout = out["runout_mm"].as_f64().unwrap();
    assert!((runout - 0.008).abs() < 0.3 * PIXEL, "{out}");
    assert!((out["max_radius_mm"].as_f64().unwrap() - (R + 0.008)).abs() < PIXEL, "{out}");
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.starts_with("z_mm,radius_mm,wear_mm\n"), "{}", &text[..40]);
    let first: Vec<f64> = text.lines().nth(1).unwrap().split(',').map(|v| v.parse().unwrap()).collect();
    // The tip worn back 2 µm; no wear of the edges (nominal + runout).
    assert!((first[0] - 0.002).abs() < PIXEL, "{first:?}");
    let worst = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(2).unwrap().parse::<f64>().unwrap())
        .filter(|w| w.is_finite())
        .skip(20) // the rows at the worn tip, where the radius changes by pixels per row
        .fold(0.0f64, |m, w| m.max(w.abs()));
    assert!(worst < PIXEL, "wear of an unworn edge: {worst}");
    // The 480 × 330 pictures' envelope, framed with a title, axes in mm
    // and a legend; the edges drawn over it.
    let picture = image::open(&png).unwrap().to_rgb8();
    assert!(picture.width() > 480 + 60 && picture.height() > 330 + 100, "{:?}", picture.dimensions());
    let red = picture.pixels().filter(|p| p.0[0] > 200 && p.0[1] < 60 && p.0[2] < 60).count();
    let green = picture.pixels().filter(|p| p.0[1] > 150 && p.0[0] < 60 && p.0[2] < 60).count();
    assert!(red > 300 && green > 300, "edges {red} and nominal {green} pixels: seen without zoom");
}

#[test]
fn tiles_by_their_stage_offsets_and_bad_pictures() {
    let dir = tempfile::tempdir().unwrap();
    let v = view(262.0, 390.0);
    let mut rng = SplitMix64::new(6);
    let truth = [[0.0, 0.0], [189.0, 0.0], [0.0, 161.0], [189.0, 161.0]];
    let stage = [[0.0, 0.0], [191.0, 1.0], [-1.5, 162.0], [187.0, 160.0]];
    let mut offsets = String::from("image,x_mm,z_mm\n");
    let mut args = vec!["tool".to_string(), "profile".to_string()];
    for (t, (at, s)) in truth.iter().zip(stage).enumerate() {
        for (k, f) in v.frames(3, 330, 260, *at, &mut rng).iter().enumerate() {
            let name = format!("t{t}-{k}.png");
            save(f, &dir.path().join(&name));
            offsets += &format!("{name},{},{}\n", s[0] * PIXEL, -s[1] * PIXEL);
            args.push(path(dir.path(), &name));
        }
    }
    std::fs::write(dir.path().join("offsets.csv"), &offsets).unwrap();
    let (csv, off) = (path(dir.path(), "t.csv"), path(dir.path(), "offsets.csv"));
    args.extend(["--pixel-um", "0.71", "--offsets", &off, "-o", &csv, "--json"].map(String::from));
    let out = json(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(out["fields"], 4);
    for (k, want) in truth.iter().enumerate() {
        let got = &out["field_offsets_px"][k];
        let off = (got[0].as_f64().unwrap() - want[0]).hypot(got[1].as_f64().unwrap() - want[1]);
        assert!(off < 0.3, "field {k}: {got} vs {want:?}");
    }
    // A picture of the backlight alone.
    let blank = GrayImage::filled(64, 48, 0.9);
    let file = dir.path().join("blank.png");
    save(&blank, &file);
    let o = kezuri(&["tool", "profile", file.to_str().unwrap(), "--pixel-um", "0.71", "-o", &csv]);
    assert!(!o.status.success());
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("no tool"), "{e}");
    // Tiles 0.1 mm apart.
    std::fs::write(dir.path().join("apart.csv"), "image,x_mm,z_mm\nt0-0.png,0,0\nt1-0.png,0.5,0\n").unwrap();
    let apart = path(dir.path(), "apart.csv");
    let (a, b) = (path(dir.path(), "t0-0.png"), path(dir.path(), "t1-0.png"));
    let o = kezuri(&["tool", "profile", &a, &b, "--pixel-um", "0.71", "--offsets", &apart, "-o", &csv]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("field 2 does not overlap"), "{e}");
    // A search of a metre: bounded by the pictures, then weighed.
    args.extend(["--search-um", "1e6"].map(String::from));
    let t = std::time::Instant::now();
    let o = kezuri(&args.iter().map(String::as_str).collect::<Vec<_>>());
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.code() == Some(1) && e.contains("a search of 330 pixels over 6 overlaps is up to 1.0e11 comparisons"),
        "{e}"
    );
    assert!(t.elapsed().as_secs() < 10, "{:?}", t.elapsed());
}

#[test]
fn eight_bit_tiff_frames_read_as_well() {
    let dir = tempfile::tempdir().unwrap();
    let v = view(240.0, 300.0);
    let mut rng = SplitMix64::new(7);
    let mut args = vec!["tool".to_string(), "profile".to_string()];
    for (k, f) in v.frames(12, 480, 330, [0.0, 0.0], &mut rng).iter().enumerate() {
        let name = path(dir.path(), &format!("f{k:02}.tif"));
        let bytes: Vec<u8> = f.pixels.iter().map(|&p| (p * 255.0).round() as u8).collect();
        image::GrayImage::from_raw(f.width as u32, f.height as u32, bytes).unwrap().save(&name).unwrap();
        args.push(name);
    }
    let csv = path(dir.path(), "t.csv");
    args.extend(["--pixel-um", "0.71", "-o", &csv, "--json"].map(String::from));
    let out = json(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(out["frames"], 12);
    // 12 frames 30° apart: the envelope's widest is within a pixel of R + runout.
    assert!((out["max_radius_mm"].as_f64().unwrap() - (R + 0.008)).abs() < PIXEL, "{out}");
    assert!((out["runout_mm"].as_f64().unwrap() - 0.008).abs() < PIXEL, "{out}");
}
