//! The design-review report in a real browser: headless Chromium opens the report of
//! `cases/cooler_hose_contact.ron` (solved and reported by the real binary) with WebGL
//! and every 3D API turned off, the page logs nothing to the console (no script
//! error), the 3D view's script has run, and the screenshot has hose-coloured pixels
//! exactly where the view's first frame puts the hose edges, on a white background.
//!
//! Skipped, with a printed reason, where no Chromium is installed (`.ci/run` installs
//! Debian's `chromium` when it can). With `STRAND_SCREENSHOT=<file.png>` the test also
//! writes the 3D view, cropped from the screenshot, to that file: the README's
//! picture (`docs/report-3d-view.png`) is made that way.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// How long one browser or `strand` run may take (loaded CI machines).
const DEADLINE: Duration = Duration::from_secs(180);

/// Screenshot size, px: wide enough for the view (900 px) and its page margins, tall
/// enough to hold everything above the view and the view itself.
const WINDOW: (u32, u32) = (1000, 3000);

/// The 3D view's size in the page, px (its SVG's `width` and `height`).
const VIEW: (usize, usize) = (900, 620);

/// The 3D view's border colour (CSS `figure svg { border: 1px solid #e1e4e8 }`).
const BORDER: [u8; 3] = [0xe1, 0xe4, 0xe8];

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Runs `command` to completion or kills it at [`DEADLINE`].
fn run(mut command: Command) -> Output {
    let shown = format!("{command:?}");
    let mut child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("{shown}: {e}"));
    let started = Instant::now();
    // Both pipes are read on threads so that a chatty child never blocks on them.
    let mut stdout = child.stdout.take().unwrap();
    let mut stderr = child.stderr.take().unwrap();
    let out = std::thread::spawn(move || {
        let mut b = Vec::new();
        let _ = std::io::Read::read_to_end(&mut stdout, &mut b);
        b
    });
    let err = std::thread::spawn(move || {
        let mut b = Vec::new();
        let _ = std::io::Read::read_to_end(&mut stderr, &mut b);
        b
    });
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if started.elapsed() > DEADLINE {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{shown}: still running after {DEADLINE:?}, killed");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    Output {
        status,
        stdout: out.join().unwrap(),
        stderr: err.join().unwrap(),
    }
}

/// The first Chromium on the PATH, if any.
fn chromium() -> Option<&'static str> {
    ["chromium", "chromium-browser", "google-chrome"]
        .into_iter()
        .find(|name| {
            Command::new(name)
                .arg("--version")
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .status()
                .is_ok_and(|s| s.success())
        })
}

/// Headless Chromium on `page` with a fresh profile in `profile`, no network
/// services, no GPU, no WebGL, console messages on stderr, plus `extra` arguments.
fn browser(chromium: &str, profile: &Path, page: &Path, extra: &[String]) -> Output {
    let mut command = Command::new(chromium);
    command
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            "--disable-webgl",
            "--disable-3d-apis",
            "--hide-scrollbars",
            "--enable-logging=stderr",
            "--v=0",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(extra)
        .arg(format!("file://{}", page.display()));
    run(command)
}

/// An RGB screenshot.
struct Image {
    width: usize,
    height: usize,
    rgb: Vec<u8>,
}

impl Image {
    fn read(path: &Path) -> Image {
        let decoder =
            png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
        let mut reader = decoder.read_info().unwrap();
        let mut buffer = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buffer).unwrap();
        assert_eq!(info.bit_depth, png::BitDepth::Eight);
        let channels = match info.color_type {
            png::ColorType::Rgb => 3,
            png::ColorType::Rgba => 4,
            other => panic!("unexpected PNG colour type {other:?}"),
        };
        let (width, height) = (info.width as usize, info.height as usize);
        let rgb = buffer[..width * height * channels]
            .chunks(channels)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        Image { width, height, rgb }
    }

    fn at(&self, x: usize, y: usize) -> [u8; 3] {
        let i = 3 * (y * self.width + x);
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }

    /// The top-left corner of the first (topmost) horizontal run of `colour` at least
    /// `length` px long.
    fn find_run(&self, colour: [u8; 3], length: usize) -> Option<(usize, usize)> {
        for y in 0..self.height {
            let mut run = 0;
            for x in 0..self.width {
                run = if self.at(x, y) == colour { run + 1 } else { 0 };
                if run == length {
                    return Some((x + 1 - length, y));
                }
            }
        }
        None
    }
}

/// Every `<line>` of class `class` in the page: `(x1, y1, x2, y2)`, px.
fn lines(doc: &roxmltree::Document, class: &str) -> Vec<[f64; 4]> {
    doc.descendants()
        .filter(|n| n.has_tag_name("line") && n.attribute("class") == Some(class))
        .map(|n| ["x1", "y1", "x2", "y2"].map(|k| n.attribute(k).unwrap().parse().unwrap()))
        .collect()
}

#[test]
fn the_report_renders_its_3d_view_in_a_headless_browser_without_errors() {
    let Some(chromium) = chromium() else {
        eprintln!(
            "SKIPPED: no chromium on the PATH (Debian: apt-get install chromium); the browser test of the report did not run"
        );
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let strand = env!("CARGO_BIN_EXE_strand");
    let results = tmp.path().join("contact");
    let mut solve = Command::new(strand);
    solve
        .arg("solve")
        .arg(repo().join("cases/cooler_hose_contact.ron"))
        .arg("--out")
        .arg(&results);
    let solved = run(solve);
    assert!(
        solved.status.success(),
        "solve: {}",
        String::from_utf8_lossy(&solved.stderr)
    );
    let page = tmp.path().join("report.html");
    let mut report = Command::new(strand);
    report.arg("report").arg(&results).arg("--out").arg(&page);
    let reported = run(report);
    assert!(
        reported.status.success(),
        "report: {}",
        String::from_utf8_lossy(&reported.stderr)
    );

    // The page as an XML document (the report is XHTML-compatible): the environment
    // and every contact of result.json are in the 3D view, with result.json's forces.
    let html = std::fs::read_to_string(&page).unwrap();
    let doc = roxmltree::Document::parse(html.strip_prefix("<!DOCTYPE html>\n").unwrap())
        .expect("the report parses as XML");
    let result: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(results.join("result.json")).unwrap())
            .unwrap();
    let contacts = result["contacts"].as_array().unwrap();
    assert!(!contacts.is_empty(), "the case is a contact case");
    let drawn: Vec<f64> = doc
        .descendants()
        .filter(|n| n.attribute("class") == Some("v3d-contact"))
        .map(|n| n.attribute("data-force-n").unwrap().parse().unwrap())
        .collect();
    let expected: Vec<f64> = contacts
        .iter()
        .map(|c| c["force_N"].as_f64().unwrap())
        .collect();
    assert_eq!(
        drawn, expected,
        "contact forces in the view against result.json"
    );
    let environment = lines(&doc, "v3d-env");
    let outline_segments: usize = result["environment"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["segments_m"].as_array().unwrap().len())
        .sum();
    assert!(outline_segments > 0);
    assert_eq!(
        environment.len(),
        outline_segments,
        "every outline segment drawn"
    );
    let edges = lines(&doc, "v3d-edge");
    let segments: usize = result["rods"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["segments"].as_u64().unwrap() as usize)
        .sum();
    assert_eq!(edges.len(), segments, "one line per hose edge");
    assert!(
        doc.descendants()
            .any(|n| n.attribute("class") == Some("v3d-part")
                && n.attribute("data-kind") == Some("junction")),
        "the junction body is drawn"
    );

    // The browser: a screenshot with WebGL off and the console on stderr.
    let shot = tmp.path().join("shot.png");
    let shown = browser(
        chromium,
        &tmp.path().join("profile-a"),
        &page,
        &[
            format!("--screenshot={}", shot.display()),
            format!("--window-size={},{}", WINDOW.0, WINDOW.1),
        ],
    );
    let log = String::from_utf8_lossy(&shown.stderr);
    assert!(shown.status.success(), "chromium failed:\n{log}");
    let console: Vec<&str> = log.lines().filter(|l| l.contains(":CONSOLE")).collect();
    assert!(
        console.is_empty(),
        "the page logged to the console:\n{}",
        console.join("\n")
    );
    // The script ran to its end (it marks the view interactive last).
    let dom = browser(
        chromium,
        &tmp.path().join("profile-b"),
        &page,
        &["--dump-dom".to_string()],
    );
    let dom_text = String::from_utf8_lossy(&dom.stdout);
    assert!(
        dom_text.contains("data-interactive=\"true\""),
        "the 3D view's script did not finish; stderr:\n{}",
        String::from_utf8_lossy(&dom.stderr)
    );

    // Find the view: the first border run as wide as the view (plus its two border
    // pixels); its user units are px, from one pixel inside the border.
    let image = Image::read(&shot);
    let (left, top) = image
        .find_run(BORDER, VIEW.0 + 2)
        .expect("the 3D view's border in the screenshot");
    assert!(
        top + VIEW.1 + 2 <= image.height,
        "the view is on the screenshot"
    );
    let (x0, y0) = (left + 1, top + 1);
    let white = [255, 255, 255];
    // Hose edges: at the middle of every edge (within 2 px: anti-aliasing, rounding)
    // the pixel is not background.
    let mut on_hose = 0;
    for [x1, y1, x2, y2] in &edges {
        let (mx, my) = (0.5 * (x1 + x2), 0.5 * (y1 + y2));
        let hit = (-2..=2).any(|dy: i64| {
            (-2..=2).any(|dx: i64| {
                let x = (x0 as f64 + mx).round() as i64 + dx;
                let y = (y0 as f64 + my).round() as i64 + dy;
                image.at(x as usize, y as usize) != white
            })
        });
        on_hose += usize::from(hit);
    }
    assert_eq!(
        on_hose,
        edges.len(),
        "hose edges drawn where the view puts them"
    );
    // A background sample: the view's top-left corner region holds nothing.
    for (x, y) in [(4, 4), (40, 4), (4, 40)] {
        assert_eq!(image.at(x0 + x, y0 + y), white, "background at ({x}, {y})");
    }
    // Most of the view is background, and a good share is drawn (hoses, parts).
    let (mut background, mut total) = (0, 0);
    for y in 0..VIEW.1 {
        for x in 0..VIEW.0 {
            total += 1;
            background += usize::from(image.at(x0 + x, y0 + y) == white);
        }
    }
    let drawn_share = 1.0 - background as f64 / total as f64;
    assert!(
        drawn_share > 0.01 && drawn_share < 0.6,
        "share of non-background pixels in the view: {drawn_share}"
    );

    if let Some(target) = std::env::var_os("STRAND_SCREENSHOT") {
        let file = std::fs::File::create(&target).unwrap();
        let mut encoder =
            png::Encoder::new(std::io::BufWriter::new(file), VIEW.0 as u32, VIEW.1 as u32);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(png::Compression::High);
        let mut writer = encoder.write_header().unwrap();
        let mut crop = Vec::with_capacity(3 * VIEW.0 * VIEW.1);
        for y in 0..VIEW.1 {
            for x in 0..VIEW.0 {
                crop.extend(image.at(x0 + x, y0 + y));
            }
        }
        writer.write_image_data(&crop).unwrap();
        eprintln!("3D view written to {}", Path::new(&target).display());
    }
}
