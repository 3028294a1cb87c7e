//! `isola figure` and `isola report`: every figure kind rendered to SVG (parsed as XML, its
//! series and labels checked, its structure snapshotted) and PNG (decoded at the size asked,
//! not blank); the report of the Fig 4 and Fig 6A sessions self-contained and complete.

use isola::analysis::orbit::scalogram::{ScalogramSpec, scalogram};
use std::collections::{BTreeMap, BTreeSet};
use std::process::Command;

use isola::analysis::Ratio;
use isola::analysis::continuation::map::MapCell;
use isola::analysis::orbit::time_history::SteadySummary;
use isola::figure::{self, Format, Options, Subject, Theme};
use isola::model::Device;
use isola::session::results::{
    AttractorRow, BasinView, BifurcationPoint, ChirpView, ContinuationView, ContinuedPoint,
    ContinuedView, CurveView, FamilyView, ForceView, HistoryView, HuntView, MapView, ResponsePoint,
    ResultView,
};

/// A response at ω_e of type `1:k`, on branch `branch`.
fn response(omega: f64, amplitude: f64, k: u32, hidden: bool, branch: usize) -> ResponsePoint {
    ResponsePoint {
        omega,
        amplitude: Some(amplitude),
        response_type: if k == 1 {
            "1:1".into()
        } else {
            format!("1:{k} subharmonic")
        },
        period: Some(k as usize),
        ratio: Some(Ratio::new(1, k)),
        hidden: Some(hidden),
        branch: Some(branch),
        share: 0.5,
        start: Some(vec![1.0, 0.0]),
    }
}

/// A frequency response as Fig 4 has it, in small: a 1:1 resonance, a hidden 1:2 branch
/// over ω_e 3.6–4.4 and collisions at two ω_e.
fn responses() -> Vec<ResponsePoint> {
    let mut points: Vec<ResponsePoint> = (0..24)
        .map(|i| {
            let w = 0.25 * (i + 1) as f64;
            response(w, 0.05 / ((w - 1.8).powi(2) + 0.1), 1, false, 0)
        })
        .collect();
    points.extend((0..5).map(|i| {
        let w = 3.6 + 0.2 * i as f64;
        response(w, 0.42 - 0.05 * i as f64, 2, true, 1)
    }));
    for w in [5.5, 5.75] {
        points.push(ResponsePoint {
            amplitude: None,
            response_type: "collision".into(),
            period: None,
            ratio: None,
            hidden: None,
            branch: None,
            start: None,
            ..response(w, 0.0, 1, false, 0)
        });
    }
    points
}

/// A continued 1:2 isola: stable above, unstable below, folds at both ends.
fn isola_branch() -> ContinuedView {
    let n = 20;
    let points = (0..=n)
        .map(|i| {
            let t = std::f64::consts::PI * i as f64 / n as f64;
            let omega = 4.0 - 0.4 * t.cos();
            let amplitude = 0.3 + 0.1 * t.sin() * if i <= n / 2 { 1.0 } else { -1.0 };
            ContinuedPoint {
                parameter: omega,
                omega,
                amplitude,
                stable: i <= n / 2,
                start: [1.0, 0.0],
            }
        })
        .collect();
    let fold = |omega: f64| BifurcationPoint {
        kind: "fold".into(),
        parameter: omega,
        omega,
        amplitude: 0.3,
    };
    ContinuedView {
        period: 2,
        verdict: "isola".into(),
        points,
        bifurcations: vec![
            fold(3.6),
            fold(4.4),
            BifurcationPoint {
                kind: "period-doubling".into(),
                ..fold(4.0)
            },
        ],
    }
}

/// A small basin: a 1:2 band across a 1:1 field, a collision in a corner.
fn basin() -> BasinView {
    let (dx, v): (Vec<f64>, Vec<f64>) = (
        (0..21).map(|i| -0.8 + 0.08 * i as f64).collect(),
        (0..25).map(|i| -1.0 + 2.0 / 24.0 * i as f64).collect(),
    );
    let mut labels = Vec::new();
    for &x in &dx {
        for &y in &v {
            labels.push(Some(if x > 0.7 && y > 0.9 {
                2
            } else if (x * x + y * y).sqrt() % 0.5 < 0.15 {
                1
            } else {
                0
            }));
        }
    }
    let count = |id| labels.iter().filter(|&&l| l == Some(id)).count();
    let row = |id: usize, response_type: &str, amplitude: Option<f64>| AttractorRow {
        id,
        response_type: response_type.into(),
        amplitude,
        cells: count(id),
        fraction: count(id) as f64 / labels.len() as f64,
        start: None,
    };
    let attractors = vec![
        row(0, "1:1", Some(0.012)),
        row(1, "1:2 subharmonic", Some(0.416)),
        row(2, "collision", None),
    ];
    BasinView {
        dx,
        v,
        labels,
        attractors,
    }
}

/// A decaying transient into a 1:2 orbit.
fn history() -> HistoryView {
    let n = 2000;
    let tau: Vec<f64> = (0..n).map(|i| 0.05 * i as f64).collect();
    let lambda: Vec<f64> = tau
        .iter()
        .map(|t| 1.02 + 0.2 * (1.85 * t).sin() + 0.3 * (-t / 20.0).exp() * (3.7 * t).cos())
        .collect();
    let v = tau.iter().map(|t| 0.37 * (1.85 * t).cos()).collect();
    HistoryView {
        steady: tau.iter().map(|&t| t > 70.0).collect(),
        tau,
        lambda,
        v,
        summary: Some(SteadySummary {
            omega: 3.7,
            period_forcing_periods: Some(2),
            amplitude: 0.4156,
            slack: Some([0.1, 0.2]),
        }),
        states: None,
        output: Vec::new(),
        collision: None,
    }
}

/// A forward chirp with a resonance at ω_e 1.8.
fn chirp() -> ChirpView {
    let dt = 0.05;
    let n = 8000;
    let omega: Vec<f64> = (0..n).map(|i| 6.0 * i as f64 / n as f64).collect();
    let mut phase = 0.0;
    let lambda = omega
        .iter()
        .map(|w| {
            phase += w * dt;
            1.0 + 0.3 / (1.0 + 8.0 * (w - 1.8f64).powi(2)) * f64::sin(phase)
        })
        .collect();
    let envelope = omega
        .iter()
        .step_by(200)
        .map(|w| [*w, 0.3 / (1.0 + 8.0 * (w - 1.8f64).powi(2))])
        .collect();
    ChirpView {
        dt,
        omega,
        lambda,
        envelope,
    }
}

fn force() -> ForceView {
    ForceView {
        curves: [1.0, 1.02, 1.05]
            .iter()
            .map(|&lambda_p| {
                let points = (0..41)
                    .map(|i| {
                        let x = -0.8 + 0.04 * i as f64;
                        [x, -(lambda_p * 2.0) * x + x.powi(3)]
                    })
                    .collect();
                (lambda_p, 0.1, points)
            })
            .collect(),
    }
}

fn family() -> FamilyView {
    FamilyView {
        parameter: "adr".into(),
        members: [0.4, 0.6, 0.8]
            .iter()
            .map(|&adr| {
                let points = responses()
                    .into_iter()
                    .map(|mut p| {
                        p.amplitude = p.amplitude.map(|a| a * adr / 0.6);
                        p
                    })
                    .collect();
                (adr, points)
            })
            .collect(),
    }
}

fn map() -> MapView {
    let omegas: Vec<f64> = (0..12).map(|i| 3.0 + 0.2 * i as f64).collect();
    let values: Vec<f64> = (0..8).map(|i| 0.2 + 0.1 * i as f64).collect();
    let rows = values
        .iter()
        .map(|&adr| {
            Some(
                omegas
                    .iter()
                    .map(|&w| {
                        let isola = adr > 0.45 && (w - 4.0).abs() < adr;
                        MapCell {
                            stable: 1 + usize::from(isola),
                            largest_amplitude: Some(if isola { 0.4 } else { 0.01 }),
                            largest_type: Some(if isola { "1:2" } else { "1:1" }.into()),
                            hidden: isola,
                            subharmonic: isola,
                            collision_share: 0.0,
                            non_periodic_share: 0.0,
                        }
                    })
                    .collect(),
            )
        })
        .collect();
    let fold = CurveView {
        kind: "fold".into(),
        period: 2,
        points: (0..=10)
            .map(|i| {
                let adr = 0.45 + 0.05 * i as f64;
                [4.0 - adr, adr]
            })
            .collect(),
        extrema: vec![("minimum".into(), "adr".into(), [3.55, 0.45])],
    };
    let pd = CurveView {
        kind: "period-doubling".into(),
        period: 1,
        points: (0..=10).map(|i| [4.0 + 0.05 * i as f64, 0.5]).collect(),
        extrema: Vec::new(),
    };
    MapView {
        x: "omega".into(),
        parameter: "adr".into(),
        omegas,
        values,
        rows,
        curves: vec![fold, pd],
    }
}

/// Every kind of figure: its name, its view, and texts its SVG must hold.
fn kinds() -> Vec<(&'static str, ResultView, Vec<&'static str>)> {
    vec![
        (
            "response",
            ResultView::Response(responses()),
            vec![
                "excitation frequency ωₑ",
                "amplitude Δλ",
                "f (Hz)",
                "amplitude Δλ·L₁ (mm)",
                "1:1",
                "1:2",
                "hidden: no sweep reaches it",
                "collision: some starts, at 2 of 28 ωₑ",
                "1:2 ωₑ 3.60–4.40",
            ],
        ),
        (
            "stepped",
            ResultView::Stepped(responses()[..24].to_vec()),
            vec!["excitation frequency ωₑ", "1:1"],
        ),
        (
            "hunt",
            ResultView::Hunt(HuntView {
                responses: responses(),
                continued: vec![isola_branch()],
            }),
            vec![
                "1:2 branch, stable (isola)",
                "unstable",
                "fold",
                "period doubling",
            ],
        ),
        (
            "basin",
            ResultView::Basin(basin()),
            vec![
                "initial offset Δλ₀",
                "initial velocity v₀",
                "Δλ₀·L₁ (mm)",
                "velocity (m/s)",
                "1:1, A 0.012",
                "1:2, A 0.416",
                "collision",
            ],
        ),
        (
            "history",
            ResultView::History(history()),
            vec!["time τ", "t (s)", "λ_I", "v", "transient", "steady 1:2"],
        ),
        (
            "chirp",
            ResultView::Chirp(chirp()),
            vec![
                "forward 0→6",
                "response frequency ωᵣ",
                "|W|/peak",
                "ωᵣ = ωₑ/2",
            ],
        ),
        (
            "force",
            ResultView::Force(force()),
            vec!["offset Δλ", "net force f_II − f_I", "λ_p 1.02, φ_I 0.1"],
        ),
        (
            "family",
            ResultView::Family(family()),
            vec!["adr = 0.4", "adr = 0.8", "hidden: no sweep reaches it"],
        ),
        (
            "continuation",
            ResultView::Continuation(ContinuationView {
                parameter: "omega".into(),
                branches: vec![isola_branch()],
            }),
            vec![
                "excitation frequency ωₑ",
                "1:2 branch, stable (isola)",
                "fold",
            ],
        ),
        (
            "map",
            ResultView::Map(map()),
            vec![
                "adr",
                "2 stable responses",
                "a hidden response",
                "fold curve",
                "period-doubling curve",
                "turning point",
            ],
        ),
    ]
}

/// Renders `view` as the CLI does, for the paper's device.
fn render(name: &str, view: &ResultView, format: Format, size: (u32, u32)) -> Vec<u8> {
    let scalogram = match view {
        ResultView::Chirp(c) => {
            Some(scalogram(&c.lambda, c.dt, &ScalogramSpec::default()).unwrap())
        }
        _ => None,
    };
    let subject = Subject {
        title: name.into(),
        view,
        device: Some(Device::silicone()),
        names: None,
        omega_range: None,
        scalogram: scalogram.as_ref(),
        reverse: None,
    };
    let options = Options {
        format,
        width: size.0,
        height: size.1,
        theme: Theme::Paper,
    };
    figure::render(&subject, &options).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Element names and how many of each: the figure's structure without its coordinates.
fn structure(doc: &roxmltree::Document) -> String {
    let mut counts: BTreeMap<&str, usize> = BTreeMap::new();
    for node in doc.descendants().filter(|n| n.is_element()) {
        *counts.entry(node.tag_name().name()).or_default() += 1;
    }
    counts
        .iter()
        .map(|(name, n)| format!("{name}: {n}\n"))
        .collect()
}

#[test]
fn every_kind_renders_to_svg_with_its_series_and_labels() {
    for (name, view, labels) in kinds() {
        let svg = String::from_utf8(render(name, &view, Format::Svg, (800, 500))).unwrap();
        let doc = roxmltree::Document::parse(&svg).unwrap_or_else(|e| panic!("{name}: {e}"));
        let root = doc.root_element();
        assert_eq!(root.tag_name().name(), "svg");
        assert_eq!(root.attribute("width"), Some("800"), "{name}");
        assert_eq!(root.attribute("height"), Some("500"), "{name}");
        let texts: Vec<&str> = doc
            .descendants()
            .filter(|n| n.has_tag_name("text"))
            .filter_map(|n| n.text().map(str::trim))
            .collect();
        assert!(texts.contains(&name), "{name}: no title in {texts:?}");
        for label in labels {
            assert!(
                texts.iter().any(|t| t.contains(label)),
                "{name}: no '{label}' in {texts:?}"
            );
        }
        // the data is drawn: markers, lines or cells, in the embedded font's family
        let drawn = doc
            .descendants()
            .filter(|n| {
                ["circle", "polygon", "polyline", "rect", "path"].contains(&n.tag_name().name())
            })
            .count();
        assert!(drawn > 20, "{name}: {drawn} shapes");
        assert!(svg.contains("DejaVu Sans"), "{name}");
        insta::assert_snapshot!(format!("svg_structure_{name}"), structure(&doc));
    }
}

/// The texts of the SVG figure: each `<text>`'s, trimmed.
fn svg_texts(svg: &str) -> Vec<String> {
    let doc = roxmltree::Document::parse(svg).unwrap();
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text().map(|t| t.trim().to_string()))
        .collect()
}

/// The streams of a PDF file: each one's dictionary and its data, inflated if compressed.
fn pdf_streams(pdf: &[u8]) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let mut at = 0;
    while let Some(i) = find(pdf, b"stream\n", at) {
        let start = i + b"stream\n".len();
        let end = find(pdf, b"\nendstream", start).expect("every stream ends");
        let object = pdf[at..i].windows(4).rposition(|w| w == b" obj").unwrap() + at;
        let dict = String::from_utf8_lossy(&pdf[object..i]).into_owned();
        let data = &pdf[start..end];
        let data = if dict.contains("/FlateDecode") {
            miniz_oxide::inflate::decompress_to_vec_zlib(data).expect("a zlib stream")
        } else {
            data.to_vec()
        };
        out.push((dict, data));
        at = end + b"\nendstream".len();
    }
    out
}

/// Where `needle` first occurs in `bytes` from `from`.
fn find(bytes: &[u8], needle: &[u8], from: usize) -> Option<usize> {
    bytes[from..]
        .windows(needle.len())
        .position(|w| w == needle)
        .map(|i| i + from)
}

/// The bytes of each literal string `( … )` in `ops` (PDF content operators), escapes read.
fn literal_strings(ops: &[u8]) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    let mut bytes = ops.iter().copied();
    while let Some(b) = bytes.next() {
        if b != b'(' {
            continue;
        }
        // balanced parentheses stand unescaped in a string
        let (mut s, mut depth) = (Vec::new(), 0);
        while let Some(b) = bytes.next() {
            match b {
                b')' if depth == 0 => break,
                b'(' | b')' => {
                    depth += if b == b'(' { 1 } else { -1 };
                    s.push(b);
                }
                b'\\' => {
                    let e = bytes.next().unwrap();
                    s.push(match e {
                        b'n' => b'\n',
                        b'r' => b'\r',
                        b't' => b'\t',
                        b'b' => 8,
                        b'f' => 12,
                        b'0'..=b'7' => {
                            // up to three octal digits: the string's glyph ids are written so
                            let mut v = u32::from(e - b'0');
                            let mut rest = bytes.clone().take(2);
                            let mut taken = 0;
                            while let Some(d @ b'0'..=b'7') = rest.next() {
                                v = 8 * v + u32::from(d - b'0');
                                taken += 1;
                            }
                            for _ in 0..taken {
                                bytes.next();
                            }
                            v as u8
                        }
                        other => other,
                    });
                }
                other => s.push(other),
            }
        }
        out.push(s);
    }
    out
}

/// The texts a PDF figure shows: each text object's glyphs (two-byte glyph ids), read back
/// to characters through the font's `ToUnicode` map, trimmed.
fn pdf_texts(pdf: &[u8]) -> Vec<String> {
    let streams = pdf_streams(pdf);
    let cmap = &streams
        .iter()
        .find(|(_, data)| data.windows(11).any(|w| w == b"beginbfchar"))
        .expect("a ToUnicode map")
        .1;
    let cmap = String::from_utf8_lossy(cmap);
    let mut chars: BTreeMap<u16, char> = BTreeMap::new();
    for line in cmap.lines().filter(|l| l.starts_with('<')) {
        let hex: Vec<u32> = line
            .split(['<', '>', ' '])
            .filter(|p| !p.is_empty())
            .map(|h| u32::from_str_radix(h, 16).unwrap())
            .collect();
        chars.insert(hex[0] as u16, char::from_u32(hex[1]).unwrap());
    }
    let content = &streams
        .iter()
        .find(|(_, data)| data.windows(3).any(|w| w == b"BT\n"))
        .expect("a page with text")
        .1;
    let mut texts = Vec::new();
    let mut at = 0;
    while let Some(begin) = find(content, b"BT\n", at) {
        let end = find(content, b"\nET", begin).expect("every text object ends");
        let mut text = String::new();
        for glyphs in literal_strings(&content[begin..end]) {
            for id in glyphs.chunks(2) {
                let id = u16::from_be_bytes([id[0], id[1]]);
                text.push(*chars.get(&id).unwrap_or_else(|| panic!("glyph {id}")));
            }
        }
        texts.push(text.trim().to_string());
        at = end;
    }
    texts
}

#[test]
fn every_kind_renders_to_a_pdf_page_showing_the_svg_texts_in_the_embedded_font() {
    for (name, view, labels) in kinds() {
        let pdf = render(name, &view, Format::Pdf, (800, 500));
        assert!(pdf.starts_with(b"%PDF-"), "{name}");
        let text = String::from_utf8_lossy(&pdf);
        // 800 × 500 pixels of 0.75 pt
        assert!(text.contains("/MediaBox [0 0 600 375]"), "{name}");
        assert_eq!(text.matches("/Type /Page\n").count(), 1, "{name}");
        for part in [
            "/Subtype /Type0",
            "/CIDFontType2",
            "+DejaVuSans",
            "/FontFile2",
        ] {
            assert!(text.contains(part), "{name}: no {part}");
        }
        // the same texts as the SVG figure, glyph for glyph
        let mut shown = pdf_texts(&pdf);
        let svg = render(name, &view, Format::Svg, (800, 500));
        let mut expected = svg_texts(&String::from_utf8(svg).unwrap());
        shown.sort();
        expected.sort();
        assert_eq!(shown, expected, "{name}");
        for label in labels {
            assert!(
                shown.iter().any(|t| t.contains(label)),
                "{name}: no '{label}' in {shown:?}"
            );
        }
        // the data is drawn: filled and stroked paths, as many as the SVG has shapes
        let page = &pdf_streams(&pdf)
            .into_iter()
            .find(|(_, data)| data.windows(3).any(|w| w == b"BT\n"))
            .unwrap()
            .1;
        let page = String::from_utf8_lossy(page);
        let painted = page.lines().filter(|l| *l == "f" || *l == "S").count();
        assert!(painted > 20, "{name}: {painted} paths");
    }
}

#[test]
fn a_response_draws_one_marker_per_response_with_hidden_ones_outlined() {
    let svg = String::from_utf8(render(
        "response",
        &ResultView::Response(responses()),
        Format::Svg,
        (800, 500),
    ))
    .unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let count = |tag: &str| doc.descendants().filter(|n| n.has_tag_name(tag)).count();
    // 24 filled 1:1 circles and one in the legend
    assert_eq!(count("circle"), 24 + 1);
    // 5 hidden 1:2 diamonds outlined (closed polylines), filled and outlined in the legend
    assert!(count("polyline") >= 6, "{}", count("polyline"));
    assert!(count("polygon") >= 1);
}

#[test]
fn every_kind_renders_to_a_png_of_the_size_asked_that_is_not_blank() {
    for (name, view, _) in kinds() {
        let bytes = render(name, &view, Format::Png, (640, 400));
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder
            .read_info()
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
        let frame = reader.next_frame(&mut pixels).unwrap();
        assert_eq!((frame.width, frame.height), (640, 400), "{name}");
        let colours: BTreeSet<&[u8]> = pixels[..frame.buffer_size()].chunks(3).collect();
        assert!(colours.len() >= 8, "{name}: {} colours", colours.len());
        // mostly background, but not only
        let white = pixels.chunks(3).filter(|p| *p == [255, 255, 255]).count();
        let all = (frame.width * frame.height) as usize;
        assert!(white < all * 98 / 100, "{name}: {white} of {all} white");
    }
}

#[test]
fn the_dark_theme_has_a_dark_background() {
    let subject = Subject {
        title: "dark".into(),
        view: &ResultView::Force(force()),
        device: None,
        names: None,
        omega_range: None,
        scalogram: None,
        reverse: None,
    };
    let bytes = figure::render(
        &subject,
        &Options {
            format: Format::Png,
            width: 200,
            height: 120,
            theme: Theme::Dark,
        },
    )
    .unwrap();
    let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    reader.next_frame(&mut pixels).unwrap();
    assert!(pixels[..3].iter().all(|&c| c < 60), "{:?}", &pixels[..3]);
}

#[test]
fn bad_sizes_and_empty_views_are_refused_saying_why() {
    let view = ResultView::Response(Vec::new());
    let subject = Subject {
        title: "empty".into(),
        view: &view,
        device: None,
        names: None,
        omega_range: None,
        scalogram: None,
        reverse: None,
    };
    let zero = Options {
        width: 0,
        ..Options::default()
    };
    let e = figure::render(&subject, &zero).unwrap_err().to_string();
    assert!(e.contains("width 0") && e.contains("8000"), "{e}");
    let e = figure::render(&subject, &Options::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("nothing to draw: no response"), "{e}");
    let e = "eps".parse::<Format>().unwrap_err().to_string();
    assert!(e.contains("'eps'") && e.contains("svg, png, pdf"), "{e}");
    let e = "neon".parse::<Theme>().unwrap_err().to_string();
    assert!(e.contains("'neon'") && e.contains("paper, dark"), "{e}");
}

fn isola(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_isola"))
        .args(args)
        .output()
        .expect("the binary runs")
}

const FIG4: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/sessions/fig04_response_adr06.toml"
);
const FIG6A: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/sessions/fig06a_basin_adr06.toml"
);

#[test]
fn figure_refuses_bad_flags_naming_the_flag_the_value_and_the_choices() {
    let stderr = |args: &[&str]| {
        let out = isola(args);
        assert!(!out.status.success(), "{args:?}");
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let e = stderr(&["figure", FIG4, "--analysis", "nope"]);
    assert!(
        e.contains("--analysis") && e.contains("'nope'") && e.contains("response, orbit_3_7_isola"),
        "{e}"
    );
    let e = stderr(&["figure", FIG4, "--analysis", "response", "--format", "eps"]);
    assert!(
        e.contains("--format") && e.contains("'eps'") && e.contains("svg, png, pdf"),
        "{e}"
    );
    for flag in ["--width", "--height"] {
        let e = stderr(&["figure", FIG4, "--analysis", "response", flag, "0"]);
        assert!(
            e.contains(flag) && e.contains("'0'") && e.contains("8000"),
            "{e}"
        );
    }
    let e = stderr(&["figure", FIG4, "--analysis", "response", "--theme", "neon"]);
    assert!(
        e.contains("--theme") && e.contains("'neon'") && e.contains("paper, dark"),
        "{e}"
    );
    let e = stderr(&[
        "figure",
        FIG4,
        "--analysis",
        "response",
        "--output",
        "x.eps",
    ]);
    assert!(
        e.contains("--output") && e.contains("'eps'") && e.contains("svg, png, pdf"),
        "{e}"
    );
}

/// The report of `session` (copied into a fresh folder, its text through `edit`), and the folder.
fn report(session: &str, edit: impl Fn(String) -> String) -> (String, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let copy = dir
        .path()
        .join(std::path::Path::new(session).file_name().unwrap());
    std::fs::write(&copy, edit(std::fs::read_to_string(session).unwrap())).unwrap();
    let out_dir = dir.path().join("out");
    let out = isola(&[
        "report",
        copy.to_str().unwrap(),
        "--output",
        out_dir.to_str().unwrap(),
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let path = summary["wrote"][0].as_str().unwrap().to_string();
    assert!(path.starts_with(out_dir.to_str().unwrap()), "{path}");
    (std::fs::read_to_string(path).unwrap(), dir)
}

/// No address outside the page: no scheme, no linked sheet, script, image or font.
fn assert_self_contained(html: &str) {
    for outside in [
        "http:", "https:", "<script", "<link", "src=", "href=", "url(", "@import",
    ] {
        assert!(!html.contains(outside), "the report holds '{outside}'");
    }
}

/// Each `<svg>…</svg>` of the page, parsed as XML.
fn figures(html: &str) -> Vec<String> {
    html.split("<svg")
        .skip(1)
        .map(|rest| {
            let svg = format!("<svg{}", &rest[..rest.find("</svg>").unwrap() + 6]);
            roxmltree::Document::parse(&svg).unwrap_or_else(|e| panic!("{e}"));
            svg
        })
        .collect()
}

#[test]
fn the_fig4_report_holds_every_figure_and_table_and_nothing_from_outside() {
    // its response from 7 × 7 starts, not 15 × 15: the report holds the same figures and
    // tables, the isola and its hidden flag among them, for 40 % of the CPU (the response
    // at the paper's resolution is `global_analyses`' test)
    let (html, _dir) = report(FIG4, |text| {
        assert_eq!(text.matches("points = 15 }").count(), 2);
        text.replace("points = 15 }", "points = 7 }")
    });
    assert_self_contained(&html);
    let svgs = figures(&html);
    // the response and five orbits
    assert_eq!(svgs.len(), 6);
    for name in [
        "response",
        "orbit_3_7_isola",
        "orbit_3_7_harmonic",
        "orbit_1_8_high",
        "orbit_1_8_low",
        "orbit_1_2",
    ] {
        assert!(html.contains(&format!("<section id=\"{name}\">")), "{name}");
    }
    assert!(svgs[0].contains("hidden: no sweep reaches it"));
    assert!(svgs[0].contains("1:2 ωₑ 3.60–5.40"));
    assert!(html.contains("<caption>Branches</caption>"));
    assert!(html.contains("<td>1:2 subharmonic</td>"));
    assert!(html.contains("<td>hidden</td>"));
    assert_eq!(html.matches("<caption>Steady state</caption>").count(), 5);
}

#[test]
fn the_fig6a_report_holds_the_basin_and_its_attractors_with_fractions() {
    let (html, _dir) = report(FIG6A, |text| text);
    assert_self_contained(&html);
    let svgs = figures(&html);
    assert_eq!(svgs.len(), 2);
    assert!(
        svgs[0].contains("1:1, A 0.012: 79.4 %"),
        "{}",
        &svgs[0][..200]
    );
    assert!(svgs[0].contains("1:2, A 0.416: 20.6 %"));
    assert!(html.contains("<caption>Attractors</caption>"));
    // 79.4 %, 20.6 % and 46 cells (0.09 %) at the corners, as MODEL.md has them
    for fraction in ["79.36 %", "20.55 %", "0.09 %"] {
        assert!(html.contains(&format!("<td>{fraction}</td>")), "{fraction}");
    }
    assert!(html.contains("<td>46</td>"));
    assert!(html.contains("<caption>Steady state</caption>"));
}

/// A written model's report speaks of its own quantities: its frequency's name in the tables'
/// headers and the hunt's bifurcations, its time `t` on the orbits' figures, no Hz (it has no
/// device) and no membranes going slack; nothing of the built-in's ω_e, τ or Δλ.
#[test]
fn a_written_models_report_carries_its_names() {
    let session = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/sessions/user_model_clearance.toml"
    );
    let (html, _dir) = report(session, |text| text.replace("points = 61", "points = 9"));
    for header in [
        "<th>w from</th>",
        "<th>w to</th>",
        "<th>at w</th>",
        "<th>w</th>",
    ] {
        assert!(html.contains(header), "no {header}");
    }
    assert!(html.contains("<td>w = 0.9073</td>"), "the 1:3 isola's fold");
    // each orbit's steady part: its period, as the basin at w 0.9 has its responses
    assert_eq!(html.matches("<caption>Steady state</caption>").count(), 2);
    assert!(html.contains("<td>1:3</td>") && html.contains("<td>1:1</td>"));
    let svgs = figures(&html);
    let orbit = svg_texts(&svgs[3]);
    assert!(
        orbit
            .iter()
            .any(|t| t == "time t" || t.starts_with("time t (")),
        "{orbit:?}"
    );
    for built_in in ["ω_e", "ωₑ", "τ", "Δλ", "Hz", "slack"] {
        assert!(!html.contains(built_in), "the built-in's {built_in}");
    }
}

#[test]
fn a_written_models_figures_carry_its_names() {
    // the clearance oscillator: states x and v, frequency w, amplitude of x; a small basin
    // and the response (0.3 s) computed first, as `figure` does
    let dir = tempfile::tempdir().unwrap();
    let session = dir.path().join("clearance.toml");
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/sessions/user_model_clearance.toml"
    ))
    .unwrap()
    .replace("points = 61", "points = 9");
    std::fs::write(&session, text).unwrap();
    for (analysis, want, not) in [
        (
            "basin_0_9",
            &["initial Δx", "initial Δv"][..],
            &["Δλ₀", "v₀"][..],
        ),
        (
            "response",
            &["amplitude of x", "w", "1:2 w 2.25–2.35, hidden"][..],
            &["ωₑ", "Δλ"][..],
        ),
    ] {
        let out = dir.path().join(format!("{analysis}.svg"));
        let run = isola(&[
            "figure",
            session.to_str().unwrap(),
            "--analysis",
            analysis,
            "--output",
            out.to_str().unwrap(),
        ]);
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let texts = svg_texts(&std::fs::read_to_string(&out).unwrap());
        for label in want {
            assert!(
                texts.iter().any(|t| t == label),
                "{analysis}: no '{label}' in {texts:?}"
            );
        }
        for label in not {
            assert!(
                !texts.iter().any(|t| t.contains(label)),
                "{analysis}: the built-in's '{label}' in {texts:?}"
            );
        }
    }
}
