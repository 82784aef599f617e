//! report.html: one self-contained, offline page (inline SVG and PNG data URIs, no script,
//! no network) to judge a run by looking at it: the sheet, each piece's distortion map,
//! before/after pictures of the 3D piece coloured by |θ − 2π|, a convergence plot per piece,
//! and the seam table with mismatches highlighted.

use std::fmt::Write;

use crate::render::{VIEWS, base64, viridis_u8};
use crate::report::Report;
use crate::seams::SEAM_MISMATCH_MM;

/// Pictures of one piece, PNG bytes.
pub struct PiecePictures {
    /// The piece before processing, one per [`VIEWS`] entry.
    pub before: Vec<Vec<u8>>,
    /// After processing, same views and framing.
    pub after: Vec<Vec<u8>>,
    /// |θ − 2π| mapped to the top of the colour scale in both (rad).
    pub defect_max: f64,
    /// The flattened piece coloured by E_h.
    pub distortion: Vec<u8>,
    /// E_h at the top of its colour scale.
    pub e_h_max: f64,
    /// Boundary loops of the flattened piece (mm), for the sheet.
    pub outline: Vec<Vec<[f64; 2]>>,
}

/// Gap between pieces on the sheet (mm).
const SHEET_GAP_MM: f64 = 20.0;

/// Size, fabric, shrink, darts and feature curves of a piece, as " · "-joined text (empty
/// when the piece has none).
fn piece_extras(p: &crate::report::PieceReport) -> String {
    let mut parts = Vec::new();
    if !p.size.is_empty() {
        parts.push(format!("size {}", p.size));
    }
    if !p.fabric.is_empty() {
        parts.push(p.fabric.clone());
    }
    let (along, across) = (p.pattern.shrink_along_grain, p.pattern.shrink_across_grain);
    if along != 0.0 || across != 0.0 {
        parts.push(format!(
            "shrink {:+.1} % along, {:+.1} % across the grain",
            100.0 * along,
            100.0 * across
        ));
    }
    if !p.darts.is_empty() {
        parts.push(format!("darts {}", p.darts.join(", ")));
    }
    for (k, f) in p.features.iter().enumerate() {
        parts.push(format!(
            "feature {k}: {:.1} mm, moved ≤ {:.3} mm",
            f.length_3d_mm, f.max_displacement_mm
        ));
    }
    parts.iter().map(|x| format!(" · {x}")).collect()
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn img(png: &[u8], alt: &str) -> String {
    format!(
        "<img alt=\"{}\" width=\"220\" height=\"220\" src=\"data:image/png;base64,{}\">",
        esc(alt),
        base64(png)
    )
}

/// A horizontal viridis colour bar from 0 to `max` (unit `unit`).
fn legend(max: f64, unit: &str) -> String {
    let mut s = String::from(
        "<svg class=\"legend\" width=\"220\" height=\"30\" viewBox=\"0 0 220 30\" xmlns=\"http://www.w3.org/2000/svg\">",
    );
    for i in 0..44 {
        let c = viridis_u8(i as f64 / 43.0);
        let _ = write!(
            s,
            "<rect x=\"{}\" y=\"0\" width=\"5\" height=\"12\" fill=\"#{:02x}{:02x}{:02x}\"/>",
            i * 5,
            c[0],
            c[1],
            c[2]
        );
    }
    let _ = write!(
        s,
        "<text x=\"0\" y=\"26\" font-size=\"11\">0</text><text x=\"220\" y=\"26\" font-size=\"11\" text-anchor=\"end\">{max:.2e} {}</text></svg>",
        esc(unit)
    );
    s
}

/// log10 θ_err against iteration, with the tolerance as a dashed line.
fn convergence_plot(history: &[f64], tolerance: f64) -> String {
    let (w, h, m) = (320.0, 170.0, 34.0);
    let logs: Vec<f64> = history.iter().map(|t| t.max(1e-16).log10()).collect();
    let tol = tolerance.max(1e-16).log10();
    let lo = logs.iter().copied().fold(tol, f64::min).floor();
    let hi = logs
        .iter()
        .copied()
        .fold(tol, f64::max)
        .ceil()
        .max(lo + 1.0);
    let n = (history.len().max(2) - 1) as f64;
    let x = |i: f64| m + (w - m - 8.0) * i / n;
    let y = |v: f64| 8.0 + (h - m - 8.0) * (hi - v) / (hi - lo);
    let mut s = format!(
        "<svg class=\"plot\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" xmlns=\"http://www.w3.org/2000/svg\">"
    );
    let _ = write!(
        s,
        "<rect x=\"{m}\" y=\"8\" width=\"{:.1}\" height=\"{:.1}\" fill=\"none\" stroke=\"#999\"/>",
        w - m - 8.0,
        h - m - 8.0
    );
    let mut d = hi;
    while d >= lo {
        let _ = write!(
            s,
            "<text x=\"{:.1}\" y=\"{:.1}\" font-size=\"10\" text-anchor=\"end\">1e{}</text>",
            m - 3.0,
            y(d) + 3.0,
            d as i64
        );
        d -= ((hi - lo) / 4.0).ceil().max(1.0);
    }
    let _ = write!(
        s,
        "<line x1=\"{m}\" x2=\"{:.1}\" y1=\"{:.1}\" y2=\"{:.1}\" stroke=\"#c00\" stroke-dasharray=\"4 3\"/>",
        w - 8.0,
        y(tol),
        y(tol)
    );
    let pts: Vec<String> = logs
        .iter()
        .enumerate()
        .map(|(i, v)| format!("{:.1},{:.1}", x(i as f64), y(*v)))
        .collect();
    let _ = write!(
        s,
        "<polyline fill=\"none\" stroke=\"#246\" stroke-width=\"1.5\" points=\"{}\"/>",
        pts.join(" ")
    );
    let _ = write!(
        s,
        "<text x=\"{:.1}\" y=\"{:.1}\" font-size=\"10\" text-anchor=\"middle\">iteration (0 … {})</text></svg>",
        (w + m) / 2.0,
        h - 6.0,
        history.len().saturating_sub(1)
    );
    s
}

/// The cutting sheet as written to sheet.svg (seam allowance, notches, grain, labels, layout,
/// quantities and mirrored copies), embedded as an SVG data URI so that the page stays one
/// self-contained file and the sheet's own ids and styles cannot clash with the page's.
fn sheet_image(sheet_svg: &[u8]) -> String {
    format!(
        "<img class=\"sheet\" alt=\"the cutting sheet (sheet.svg)\" src=\"data:image/svg+xml;base64,{}\">",
        base64(sheet_svg)
    )
}

/// Without sheet.svg (no `svg` among the formats): every piece's flattened outline side by
/// side at true relative size, without allowance or layout.
fn sheet(report: &Report, pictures: &[PiecePictures]) -> String {
    let mut x0 = 0.0;
    let mut height: f64 = 0.0;
    let mut body = String::new();
    for (p, pic) in report.pieces.iter().zip(pictures) {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for q in pic.outline.iter().flatten() {
            for k in 0..2 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        }
        if !lo[0].is_finite() {
            continue;
        }
        let mut d = String::new();
        for lp in &pic.outline {
            for (i, q) in lp.iter().enumerate() {
                // y flipped: SVG rows grow downwards, the pattern's grain points up.
                let _ = write!(
                    d,
                    "{}{:.2} {:.2} ",
                    if i == 0 { "M" } else { "L" },
                    x0 + q[0] - lo[0],
                    hi[1] - q[1]
                );
            }
            d.push_str("Z ");
        }
        let _ = write!(
            body,
            "<path d=\"{}\" fill=\"#eef\" stroke=\"#c00\" stroke-width=\"1\" vector-effect=\"non-scaling-stroke\"/><text x=\"{:.2}\" y=\"{:.2}\" font-size=\"{:.1}\" text-anchor=\"middle\">{}</text>",
            d.trim_end(),
            x0 + (hi[0] - lo[0]) / 2.0,
            (hi[1] - lo[1]) / 2.0,
            ((hi[0] - lo[0]).min(hi[1] - lo[1]) / 12.0).clamp(6.0, 30.0),
            esc(&p.name)
        );
        x0 += hi[0] - lo[0] + SHEET_GAP_MM;
        height = height.max(hi[1] - lo[1]);
    }
    let width = (x0 - SHEET_GAP_MM).max(1.0);
    format!(
        "<svg class=\"sheet\" viewBox=\"-5 -5 {:.2} {:.2}\" xmlns=\"http://www.w3.org/2000/svg\">{body}</svg>",
        width + 10.0,
        height.max(1.0) + 10.0
    )
}

/// The whole page.
///
/// `sheet_svg` is the bytes of sheet.svg when the run writes it; without it the page shows the
/// flattened outlines instead, and says so.
pub fn report_html(
    report: &Report,
    pictures: &[PiecePictures],
    sheet_svg: Option<&[u8]>,
    tolerance_rad: f64,
) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>flatcut run: {name}</title>\
<style>body{{font-family:sans-serif;margin:2em;color:#222}}table{{border-collapse:collapse;margin:1em 0}}\
td,th{{border:1px solid #ccc;padding:2px 8px;text-align:right}}th{{background:#f4f4f4}}td.l,th.l{{text-align:left}}\
tr.bad td{{background:#fdd}}.sheet{{width:100%;max-height:420px;border:1px solid #ccc}}figure{{display:inline-block;margin:4px}}\
figcaption{{text-align:center;font-size:12px}}.piece{{border-top:1px solid #ccc;margin-top:1.5em}}code{{font-size:12px}}</style>\
<link rel=\"icon\" href=\"data:,\"></head><body>",
        name = esc(&report.pipeline)
    );
    let _ = writeln!(
        s,
        "<h1>{}</h1><p>flatcut {} · schema {} · units {} · pipeline <code>{}</code> sha256 <code>{}</code></p>",
        esc(&report.pipeline),
        esc(&report.flatcut_version),
        report.schema,
        esc(&report.units),
        esc(&report.toml.path),
        esc(&report.toml.sha256)
    );
    if !report.inputs.is_empty() {
        s.push_str("<table><tr><th class=\"l\">input</th><th class=\"l\">path</th><th>bytes</th><th class=\"l\">sha256</th></tr>");
        for i in &report.inputs {
            let _ = write!(
                s,
                "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td><td class=\"l\"><code>{}</code></td></tr>",
                esc(&i.key),
                esc(&i.path),
                i.bytes,
                esc(&i.sha256)
            );
        }
        s.push_str("</table>\n");
    }
    if let Some(g) = &report.generator {
        let _ = writeln!(
            s,
            "<p>generated input: <code>{}</code></p>",
            esc(&g.to_string())
        );
    }
    for w in &report.warnings {
        let _ = writeln!(s, "<p style=\"color:#a00\">warning: {}</p>", esc(w));
    }

    s.push_str("<h2>Sheet</h2>\n");
    match sheet_svg {
        Some(svg) => s.push_str(&sheet_image(svg)),
        None => {
            s.push_str("<p>No sheet.svg in this run's formats: the flattened outlines (sew lines, no allowance).</p>");
            s.push_str(&sheet(report, pictures));
        }
    }

    s.push_str("\n<h2>Pieces</h2><table><tr><th class=\"l\">piece</th><th>faces</th><th>θ_err before</th><th>θ_err after</th><th>it</th><th>RMS disp mm</th><th>max disp mm</th><th>area %</th><th>crease °</th><th>E_h mean</th><th>E_h p95</th><th>E_h max</th><th>E_r mean</th><th>E_r p95</th><th>E_r max</th><th>max strain</th><th>boundary 3D mm</th><th>boundary 2D mm</th></tr>");
    for p in &report.pieces {
        let bad = !p.process.converged || p.flatten.flipped_faces > 0;
        let _ = write!(
            s,
            "<tr{}><td class=\"l\">{}</td><td>{}</td><td>{:.2e}</td><td>{:.2e}</td><td>{}</td><td>{:.3}</td><td>{:.3}</td><td>{:+.3}</td><td>{}</td><td>{:.2e}</td><td>{:.2e}</td><td>{:.2e}</td><td>{:.2e}</td><td>{:.2e}</td><td>{:.2e}</td><td>{:.2e}</td><td>{:.2}</td><td>{:.2}</td></tr>",
            if bad { " class=\"bad\"" } else { "" },
            esc(&p.name),
            p.faces,
            p.process.theta_err_before,
            p.process.theta_err_after,
            p.process.iterations,
            p.process.rms_displacement_mm,
            p.process.max_displacement_mm,
            p.process.area_change_percent,
            if p.process.creased_edges > 0 {
                format!(
                    "{:.0} ({} edges{})",
                    p.process.max_crease_deg,
                    p.process.creased_edges,
                    flatcut_flattenable::CreaseKind::of(p.process.creased_defect_rad)
                        .map_or(String::new(), |k| format!("; {}", esc(k.advice())))
                )
            } else {
                format!("{:.0}", p.process.max_crease_deg)
            },
            p.flatten.e_h.mean,
            p.flatten.e_h.p95,
            p.flatten.e_h.max,
            p.flatten.e_r.mean,
            p.flatten.e_r.p95,
            p.flatten.e_r.max,
            p.flatten.max_edge_strain,
            p.flatten.boundary_3d_mm,
            p.flatten.boundary_2d_mm
        );
    }
    s.push_str("</table>\n");

    s.push_str("<h2>Seams</h2>\n");
    if report.seam_table.is_empty() {
        s.push_str("<p>No seams: the pieces were not cut from one surface.</p>\n");
    } else {
        let _ = write!(
            s,
            "<p>Rows in red: mates differ by more than {SEAM_MISMATCH_MM} mm in 2D.</p><table><tr><th class=\"l\">seam</th><th class=\"l\">kind</th><th class=\"l\">a</th><th class=\"l\">b</th><th>3D mm</th><th>a 2D mm</th><th>b 2D mm</th><th>a − b mm</th></tr>"
        );
        for r in &report.seam_table {
            let _ = write!(
                s,
                "<tr{}><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{:.2}</td><td>{:.2}</td><td>{:.2}</td><td>{:+.3}</td></tr>",
                if r.mismatch { " class=\"bad\"" } else { "" },
                esc(&r.id),
                if r.kind == flatcut_mesh::SeamKind::Dart {
                    "dart"
                } else {
                    "seam"
                },
                esc(&r.a_piece),
                esc(&r.b_piece),
                r.length_3d_mm,
                r.a_2d_mm,
                r.b_2d_mm,
                r.difference_mm
            );
        }
        s.push_str("</table>\n");
    }

    for (p, pic) in report.pieces.iter().zip(pictures) {
        let _ = writeln!(
            s,
            "<div class=\"piece\"><h3>{}</h3><p>{} faces · {} boundary loop(s) · cut {}{} · pattern {:.1} × {:.1} mm{}</p>",
            esc(&p.name),
            p.faces,
            p.boundary_loops,
            p.quantity,
            if p.mirror { ", mirrored" } else { "" },
            p.pattern.size_mm[0],
            p.pattern.size_mm[1],
            esc(&piece_extras(p))
        );
        let _ = write!(
            s,
            "<figure>{}<figcaption>pattern, E_h = |σ1σ2 − 1|</figcaption>{}</figure>",
            img(
                &pic.distortion,
                "flattened piece coloured by area distortion"
            ),
            legend(pic.e_h_max, "")
        );
        let _ = writeln!(
            s,
            "<figure>{}<figcaption>θ_err per iteration (rad); dashed: tolerance</figcaption></figure><br>",
            convergence_plot(&p.process.theta_err_history, tolerance_rad)
        );
        for (k, v) in VIEWS.iter().enumerate() {
            if let Some(png) = pic.before.get(k) {
                let _ = write!(
                    s,
                    "<figure>{}<figcaption>before, {}</figcaption></figure>",
                    img(
                        png,
                        &format!("{} before processing, {} view", p.name, v.name)
                    ),
                    v.name
                );
            }
        }
        s.push_str("<br>");
        for (k, v) in VIEWS.iter().enumerate() {
            if let Some(png) = pic.after.get(k) {
                let _ = write!(
                    s,
                    "<figure>{}<figcaption>after, {}</figcaption></figure>",
                    img(
                        png,
                        &format!("{} after processing, {} view", p.name, v.name)
                    ),
                    v.name
                );
            }
        }
        let _ = writeln!(
            s,
            "<p>|θ − 2π| (rad), same scale before and after:</p>{}</div>",
            legend(pic.defect_max, "rad")
        );
    }
    s.push_str("</body></html>\n");
    s
}
