//! The writers read back by independent parsers: SVG by an XML parser, DXF by the dxf crate,
//! PNG by tiny-skia's decoder, EXR by the exr crate; golden files for SVG, DXF and PNG.

#![allow(clippy::unwrap_used)]

mod common;

use common::{golden, sample};
use flatcut_export::{
    DxfOptions, DxfVersion, ExrOptions, Field, Paper, PdfOptions, PngOptions, SvgOptions, dxf_aama,
    piece_exr, piece_png, piece_svg, sheet_png, sheet_svg, tiled_pdf,
};

fn attr_mm(node: &roxmltree::Node, name: &str) -> f64 {
    node.attribute(name)
        .unwrap()
        .trim_end_matches("mm")
        .parse()
        .unwrap()
}

#[test]
fn svg_is_valid_true_scale_and_layered() {
    let (pieces, lay) = sample();
    let bytes = piece_svg(&pieces[0], &SvgOptions::default());
    let text = std::str::from_utf8(&bytes).unwrap();
    let doc = roxmltree::Document::parse(text).unwrap();
    let svg = doc.root_element();
    let b = flatcut_pattern::geom::bbox(&pieces[0].cut_line);
    // 100 + 10 (allowance, mitred square corners) × 2 + 10 margin × 2 = 140 mm wide.
    assert!((attr_mm(&svg, "width") - 140.0).abs() < 1e-3);
    assert!((attr_mm(&svg, "height") - (b[1][1] - b[0][1] + 20.0)).abs() < 1e-3);
    let vb: Vec<f64> = svg
        .attribute("viewBox")
        .unwrap()
        .split(' ')
        .map(|x| x.parse().unwrap())
        .collect();
    assert_eq!(vb[2], attr_mm(&svg, "width"));
    assert_eq!(vb[3], attr_mm(&svg, "height"));
    for layer in ["cut", "sew", "notch", "grain", "dart", "label", "internal"] {
        let g = doc
            .descendants()
            .find(|n| n.attribute("data-layer") == Some(layer))
            .unwrap_or_else(|| panic!("layer {layer}"));
        assert!(g.has_tag_name("g"));
    }
    let cut = doc
        .descendants()
        .find(|n| n.attribute("id") == Some("front-left-cut-line"))
        .unwrap();
    let cut_group = cut.parent_element().unwrap();
    assert_eq!(cut_group.attribute("stroke"), Some("#ff0000"));
    assert_eq!(cut_group.attribute("stroke-width"), Some("0.010"));
    // The seam path carries its id and length (60 mm).
    let seam = doc
        .descendants()
        .find(|n| n.attribute("data-seam-id") == Some("centre/0") && n.has_tag_name("path"))
        .unwrap();
    let len: f64 = seam.attribute("data-length-mm").unwrap().parse().unwrap();
    assert!((len - 60.0).abs() < 1e-3);
    // Ids are unique.
    let ids: Vec<&str> = doc
        .descendants()
        .filter_map(|n| n.attribute("id"))
        .collect();
    let set: std::collections::HashSet<_> = ids.iter().collect();
    assert_eq!(set.len(), ids.len());
    // The label keeps the non-ASCII fabric name, escaped as XML requires.
    assert!(text.contains("neoprène 3 mm"));
    golden("front-left.svg", &bytes);

    let sheet = sheet_svg(&pieces, &lay, &SvgOptions::default());
    let doc = roxmltree::Document::parse(std::str::from_utf8(&sheet).unwrap()).unwrap();
    let square = doc
        .descendants()
        .find(|n| {
            n.parent().and_then(|p| p.attribute("id")) == Some("test-square")
                && n.has_tag_name("rect")
        })
        .unwrap();
    assert_eq!(attr_mm(&square, "width"), 50.0);
    assert_eq!(attr_mm(&doc.root_element(), "width"), 400.0);
    // Three copies (the mirrored pair and one right piece), each with its cut line.
    let cuts = doc
        .descendants()
        .filter(|n| n.attribute("id").is_some_and(|i| i.ends_with("-cut-line")))
        .count();
    assert_eq!(cuts, 3);
}

#[test]
fn dxf_reads_back_with_pieces_layers_and_vertices() {
    let (pieces, lay) = sample();
    for version in [DxfVersion::R12, DxfVersion::R13] {
        let bytes = dxf_aama(&pieces, &lay, &DxfOptions { version }).unwrap();
        assert!(bytes.iter().all(|b| b.is_ascii()), "7-bit ASCII only");
        let drawing = dxf::Drawing::load(&mut std::io::Cursor::new(&bytes)).unwrap();
        let blocks: Vec<&dxf::Block> = drawing
            .blocks()
            .filter(|b| !b.name.starts_with('*'))
            .collect();
        assert_eq!(blocks.len(), pieces.len(), "{version:?}");
        for (piece, block) in pieces.iter().zip(&blocks) {
            assert_eq!(block.name, flatcut_export::dxf_aama::block_name(piece));
            let mut layers: Vec<&str> = block
                .entities
                .iter()
                .map(|e| e.common.layer.as_str())
                .collect();
            layers.sort();
            layers.dedup();
            let want: Vec<&str> = if piece.internal_lines.is_empty() {
                vec!["1", "14", "4", "7"]
            } else {
                vec!["1", "14", "4", "7", "8"]
            };
            assert_eq!(layers, want, "{version:?} {}", piece.name);
            let polys = |layer: &str| -> Vec<Vec<[f64; 2]>> {
                block
                    .entities
                    .iter()
                    .filter(|e| e.common.layer == layer)
                    .filter_map(|e| match &e.specific {
                        dxf::entities::EntityType::Polyline(p) => {
                            Some(p.vertices().map(|v| [v.location.x, v.location.y]).collect())
                        }
                        _ => None,
                    })
                    .collect()
            };
            for (layer, line) in [("1", &piece.cut_line), ("14", &piece.sew_line)] {
                let got = polys(layer);
                assert_eq!(got.len(), 1);
                assert_eq!(got[0].len(), line.len());
                for (a, b) in got[0].iter().zip(line.iter()) {
                    assert!(
                        (a[0] - b[0]).abs() <= 1e-3 && (a[1] - b[1]).abs() <= 1e-3,
                        "{a:?} {b:?}"
                    );
                }
            }
            let notches = block
                .entities
                .iter()
                .filter(|e| {
                    e.common.layer == "4"
                        && matches!(e.specific, dxf::entities::EntityType::Line(_))
                })
                .count();
            assert_eq!(notches, piece.notches.len());
            let texts: Vec<String> = block
                .entities
                .iter()
                .filter_map(|e| match &e.specific {
                    dxf::entities::EntityType::Text(t) => Some(t.value.clone()),
                    _ => None,
                })
                .collect();
            assert!(
                texts.contains(&format!("Piece Name: {}", piece.name)),
                "{texts:?}"
            );
            assert!(texts.contains(&format!("Quantity: {}", piece.meta.quantity)));
        }
        if version == DxfVersion::R12 {
            let text = String::from_utf8(bytes.clone()).unwrap();
            assert!(
                text.contains("Material: neoprene 3 mm"),
                "accent folded to ASCII"
            );
            assert!(
                !text.contains("TABLES"),
                "strict R12: HEADER, BLOCKS, ENTITIES only"
            );
            golden("sample.dxf", &bytes);
        }
    }
}

#[test]
fn png_piece_and_sheet() {
    let (pieces, lay) = sample();
    let opts = PngOptions {
        px_per_mm: 1.0,
        field: Field::EH,
        max_value: Some(0.01),
    };
    let bytes = piece_png(&pieces[1], &opts).unwrap();
    let pm = tiny_skia::Pixmap::decode_png(&bytes).unwrap();
    // 100 × 80 mm cut box at 1 px/mm plus 2 × 20 px margin and a 110 px legend.
    assert_eq!(pm.width(), 100 + 40 + 110);
    golden("front-right-e_h.png", &bytes);
    // A piece without edge strain values is refused, naming the piece.
    let e = piece_png(
        &pieces[1],
        &PngOptions {
            field: Field::EdgeStrain,
            ..opts.clone()
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("front-right"), "{e}");

    // The sheet: the blue test square measures 50 mm at the chosen resolution.
    let s = 2.0;
    let bytes = sheet_png(
        &pieces,
        &lay,
        &PngOptions {
            px_per_mm: s,
            ..opts
        },
    )
    .unwrap();
    let pm = tiny_skia::Pixmap::decode_png(&bytes).unwrap();
    let blue: Vec<(u32, u32)> = (0..pm.height())
        .flat_map(|y| (0..pm.width()).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let p = pm.pixel(x, y).unwrap();
            (p.red(), p.green(), p.blue()) == (0, 0, 255)
        })
        .collect();
    let xs = blue.iter().map(|p| p.0);
    let w = xs.clone().max().unwrap() - xs.min().unwrap() + 1;
    assert_eq!(w as f64, 50.0 * s);
}

#[test]
fn exr_has_float_channels_and_pixel_size() {
    use exr::prelude::ReadChannels as _;
    use exr::prelude::ReadLayers as _;
    let (pieces, _) = sample();
    let bytes = piece_exr(&pieces[1], &ExrOptions { pixel_mm: 2.0 }).unwrap();
    let bytes_again = bytes.clone();
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes))
        .unwrap();
    let layer = &image.layer_data[0];
    assert_eq!(layer.size.0, 40, "80 mm / 2 mm");
    assert_eq!(layer.size.1, 30, "60 mm / 2 mm");
    let px = layer
        .attributes
        .other
        .get(&exr::meta::attribute::Text::from("pixelSizeMm"))
        .unwrap();
    assert!(matches!(px, exr::meta::attribute::AttributeValue::F32(v) if *v == 2.0));
    // The origin is the data-window position on the global 2 mm grid.
    let bb = flatcut_pattern::geom::bbox(&pieces[1].sew_line);
    assert_eq!(
        (
            layer.attributes.layer_position.0,
            layer.attributes.layer_position.1
        ),
        (
            (bb[0][0] / 2.0).floor() as i32,
            (-bb[1][1] / 2.0).floor() as i32
        )
    );
    // Same piece, same options: the same bytes (no HashMap order, no parallel chunk order).
    for _ in 0..3 {
        assert_eq!(
            piece_exr(&pieces[1], &ExrOptions { pixel_mm: 2.0 }).unwrap(),
            bytes_again
        );
    }
    let names: Vec<String> = layer
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    assert_eq!(names, vec!["A", "E_h", "E_r"]);
    let e_h = match &layer.channel_data.list[1].sample_data {
        exr::image::FlatSamples::F32(v) => v.clone(),
        _ => panic!("float32"),
    };
    let alpha = match &layer.channel_data.list[0].sample_data {
        exr::image::FlatSamples::F32(v) => v.clone(),
        _ => panic!("float32"),
    };
    // Every pixel centre of this rectangle is inside it.
    assert!(alpha.iter().all(|a| *a == 1.0));
    // Each pixel holds the value of the face containing its centre, found here by brute force.
    let p = &pieces[1];
    let origin = flatcut_pattern::geom::bbox(&p.sew_line);
    for (row, col) in [(0usize, 0usize), (7, 13), (29, 39), (15, 20)] {
        let q = [
            origin[0][0] + (col as f64 + 0.5) * 2.0,
            origin[1][1] - (row as f64 + 0.5) * 2.0,
        ];
        let face = p
            .mesh
            .faces
            .iter()
            .position(|f| {
                let t: Vec<[f64; 2]> = f.iter().map(|&v| p.uv[v as usize]).collect();
                flatcut_pattern::geom::point_in_polygon(q, &t)
            })
            .unwrap();
        assert_eq!(
            e_h[row * 40 + col],
            p.e_h[face] as f32,
            "pixel ({row}, {col})"
        );
    }
}

#[test]
fn pdf_tiles_with_valid_xref() {
    let (pieces, lay) = sample();
    for paper in [Paper::A4, Paper::Letter] {
        let opts = PdfOptions {
            paper,
            ..Default::default()
        };
        let (cols, rows, _, _) = flatcut_export::pdf::tiles(&lay, &opts).unwrap();
        let bytes = tiled_pdf(&pieces, &lay, &opts).unwrap();
        let text = String::from_utf8(bytes).unwrap();
        assert_eq!(text.matches("/Type /Page ").count(), cols * rows);
        // A 400 mm wide sheet needs 3 columns of A4 (190 mm printable, 15 mm overlap).
        if paper == Paper::A4 {
            assert_eq!(cols, 3);
        }
        // Every xref offset points at its object.
        let start: usize = text
            .rsplit("startxref\n")
            .next()
            .unwrap()
            .lines()
            .next()
            .unwrap()
            .parse()
            .unwrap();
        let xref = &text[start..];
        for (i, line) in xref
            .lines()
            .skip(3)
            .take_while(|l| l.ends_with(" n "))
            .enumerate()
        {
            let off: usize = line[..10].parse().unwrap();
            assert!(
                text[off..].starts_with(&format!("{} 0 obj", i + 1)),
                "object {}",
                i + 1
            );
        }
        assert!(text.contains("page 1 of"));
    }
    let bad = PdfOptions {
        overlap_mm: -1.0,
        ..Default::default()
    };
    assert!(
        tiled_pdf(&pieces, &lay, &bad)
            .unwrap_err()
            .to_string()
            .contains("overlap_mm")
    );
}
