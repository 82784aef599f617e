//! True size in a browser: headless Chromium renders sheet.svg and the 50 mm test square must
//! measure 50 mm at CSS's 96/25.4 px per mm. Runs when FLATCUT_CHROMIUM names the Chromium
//! binary (e.g. /usr/bin/chromium); FAILS if it is set but the binary is missing; passes
//! without running when it is unset.

#![allow(clippy::unwrap_used)]

mod common;

use std::process::Command;

use flatcut_export::{SvgOptions, sheet_svg};

/// CSS pixels per mm at device scale factor 1 (CSS fixes 96 px per inch).
const CSS_PX_PER_MM: f64 = 96.0 / 25.4;

#[test]
fn sheet_svg_renders_at_true_size_in_chromium() {
    let Ok(bin) = std::env::var("FLATCUT_CHROMIUM") else {
        eprintln!("FLATCUT_CHROMIUM unset: true-size check skipped");
        return;
    };
    assert!(
        std::path::Path::new(&bin).is_file(),
        "FLATCUT_CHROMIUM={bin} is not a file: install chromium or unset the variable"
    );
    let (pieces, lay) = common::sample();
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("sheet.svg");
    std::fs::write(&svg, sheet_svg(&pieces, &lay, &SvgOptions::default())).unwrap();
    // An HTML page showing the SVG at its own size, at the top-left, no margins.
    let html = dir.path().join("sheet.html");
    std::fs::write(
        &html,
        "<!doctype html><html><body style=\"margin:0;background:#fff\"><img src=\"sheet.svg\"></body></html>",
    )
    .unwrap();
    let png = dir.path().join("shot.png");
    let (w, h) = (
        (lay.width_mm * CSS_PX_PER_MM).ceil() as u32 + 20,
        (lay.height_mm * CSS_PX_PER_MM).ceil() as u32 + 20,
    );
    let status = Command::new(&bin)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            "--force-device-scale-factor=1",
            &format!("--user-data-dir={}", dir.path().join("profile").display()),
            &format!("--window-size={w},{h}"),
            &format!("--screenshot={}", png.display()),
        ])
        .arg(format!("file://{}", html.display()))
        .status()
        .unwrap();
    assert!(status.success(), "chromium failed: {status}");
    let pm = tiny_skia::Pixmap::load_png(&png).unwrap();
    // Measure the blue square's extent in a window 8 mm larger than it on every side (grain
    // lines are blue too, and lie outside that window: the layout keeps a 10 mm gap).
    let ts = lay.test_square;
    let win = |lo_mm: f64, hi_mm: f64| {
        (
            (lo_mm * CSS_PX_PER_MM).floor().max(0.0) as u32,
            (hi_mm * CSS_PX_PER_MM).ceil() as u32,
        )
    };
    let (x0, x1) = win(ts[0] - 8.0, ts[0] + 58.0);
    let top = lay.height_mm - ts[1] - 50.0;
    let (y0, y1) = win(top - 8.0, top + 58.0);
    let blue = |x: u32, y: u32| {
        let p = pm.pixel(x, y).unwrap();
        p.blue() > 200 && p.red() < 60 && p.green() < 60
    };
    let pts: Vec<(u32, u32)> = (0..pm.height())
        .filter(|y| (y0..y1).contains(y))
        .flat_map(|y| (x0..x1.min(pm.width())).map(move |x| (x, y)))
        .filter(|&(x, y)| blue(x, y))
        .collect();
    assert!(!pts.is_empty(), "no test square in the screenshot");
    let span = |v: Vec<u32>| (v.iter().max().unwrap() - v.iter().min().unwrap() + 1) as f64;
    let wpx = span(pts.iter().map(|p| p.0).collect());
    let hpx = span(pts.iter().map(|p| p.1).collect());
    let want = 50.0 * CSS_PX_PER_MM; // 188.98 px
    eprintln!("test square: {wpx} × {hpx} px, want {want:.2}");
    // One pixel of antialiasing either way.
    assert!(
        (wpx - want).abs() <= 1.5,
        "square is {wpx} px wide, want {want}"
    );
    assert!(
        (hpx - want).abs() <= 1.5,
        "square is {hpx} px tall, want {want}"
    );
}
