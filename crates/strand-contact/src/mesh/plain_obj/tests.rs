//! The plain reader against tobj: the same vertices (bit for bit) and triangles on
//! every OBJ file of the repository, on hand-written edge cases and on seeded random
//! files cut into pieces in every way; and tobj's reading for what is not plain.

use std::path::{Path, PathBuf};

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{ObjTriangles, read_in_pieces, read_plain_obj};
use crate::mesh::load_obj::tobj_triangles;

/// The positions as bits (so `-0.0`, `0.0` and NaNs are told apart) and the triangles.
fn bits(t: &ObjTriangles) -> (Vec<[u64; 3]>, Vec<[u32; 3]>) {
    let positions = t.positions.iter().map(|p| p.map(f64::to_bits)).collect();
    (positions, t.triangles.clone())
}

/// Whether the plain reader took `text` (in `pieces` pieces); when it did, asserts
/// that tobj reads the same.
fn agrees_with_tobj(text: &[u8], pieces: usize) -> bool {
    let Some(plain) = read_in_pieces(text, pieces) else {
        return false;
    };
    let tobj = tobj_triangles(Path::new("test.obj"), text).unwrap_or_else(|e| {
        panic!(
            "tobj fails ({e}) on a file the plain reader took:\n{}",
            String::from_utf8_lossy(text)
        )
    });
    assert_eq!(
        bits(&plain),
        bits(&tobj),
        "{pieces} pieces of\n{}",
        String::from_utf8_lossy(text)
    );
    true
}

/// Every `.obj` below `dir`, outside `target` and hidden folders.
fn obj_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if path.is_dir() {
            if name != "target" && !name.starts_with('.') {
                obj_files(&path, out);
            }
        } else if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("obj"))
        {
            out.push(path);
        }
    }
}

#[test]
fn every_obj_file_of_the_repository_reads_as_tobj_reads_it() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files = Vec::new();
    obj_files(&root, &mut files);
    let mut plain = Vec::new();
    for file in &files {
        let bytes = std::fs::read(file).unwrap();
        for pieces in [1, 2, 3, 7] {
            if agrees_with_tobj(&bytes, pieces) && pieces == 1 {
                plain.push(file.file_name().unwrap().to_string_lossy().into_owned());
            }
        }
    }
    // The assets (engine bay, parts) are plain; the fuzz corpus mostly is not.
    for name in ["engine.obj", "radiator.obj", "v_groove.obj", "box.obj"] {
        assert!(
            plain.iter().any(|p| p == name),
            "{name} not read as plain: {plain:?}"
        );
    }
    assert!(files.len() >= 20, "{} OBJ files found", files.len());
}

#[test]
fn edge_cases_of_the_plain_subset_read_as_tobj_reads_them() {
    let plain: &[&str] = &[
        // Negative references, a quad and a pentagon (fans), a vertex used by two
        // models (o and g), vertices never used, forward of the first use order.
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 9 9 9\nf -4 -3 -2\nf 1 3 4 2\n\
         o second\nv 0 0 1\nv 2 0 1\nf 1 6 7 3 2\ng third\ng\nf 7 6 1\n",
        // Texture and normal references, CRLF, tabs, vertical tab, form feed, blanks.
        "mtllib parts.mtl\r\nv 0 0 0\r\nv 1.5 0 0\r\nv 0 -2.25 0\r\nvt 0 0\r\nvt 1 0 0\r\n\
         vn 0 0 1\r\n\r\nusemtl steel\r\nf 1/1/1 2/2/1 3/1/1\r\n\tf\t3//1  2//1\x0b1//1\x0c\r\n\
         f 1/2 3/-1 2/1/\r\ns off\r\n# done\r\n",
        // Exponents, signs, NaN-free odd spellings std accepts.
        "v 1e3 -2E-2 +.5\nv -0 0.0 1.\nv 12345678901234567890 0.1 3\nf 1 2 3\n",
        // Non-ASCII comments and names; a no-break space splitting words.
        "# π ≈ 3.14159\no pièce\nv 0 0 0\nv 1 0 0\u{a0}\nv 0 1 0\nf 1 2 3\u{2003}\n",
        // No faces, an empty file, a file without a final newline.
        "v 0 0 0\nv 1 0 0\n",
        "",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3",
        // Texture references to nothing when the file has no texture coordinates.
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/7/9 2/7/9 3/7/9\n",
        // A non-finite coordinate (the loader reports it, not the reader).
        "v nan 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n",
    ];
    for text in plain {
        for pieces in 1..=4 {
            assert!(
                agrees_with_tobj(text.as_bytes(), pieces),
                "not plain: {text:?}"
            );
        }
    }
    let not_plain: &[&[u8]] = &[
        b"v 0 0 0 2\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",     // weight
        b"v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", // colour
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n",         // a line element
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3\n",       // l
        b"v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n",       // forward reference
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",       // zero
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf +1 2 3\n",      // plus sign
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n",      // before the first
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1/1 2 3\n", // four numbers
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/2 2/1 3/1\n", // texture beyond
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl\tsteel\nf 1 2 3\n", // tobj wants a space
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n",       // not a number
        b"v 0 0 0\nv 1 0 0\nv 0 1 \xff\nf 1 2 3\n",    // not UTF-8
        b"v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",         // two coordinates
    ];
    for text in not_plain {
        assert!(
            read_plain_obj(text).is_none(),
            "{}",
            String::from_utf8_lossy(text)
        );
    }
}

/// A seeded random file: vertices in every spelling, faces of 3 to 6 references
/// (absolute or negative, with texture and normal references or not), models,
/// comments, blank lines and CRLF, all within the plain subset.
fn random_plain_obj(rng: &mut ChaCha8Rng) -> String {
    let mut text = String::new();
    let (mut vertices, mut texcoords, mut normals) = (0i64, 0i64, 0i64);
    let newline = if rng.random_bool(0.2) { "\r\n" } else { "\n" };
    for _ in 0..rng.random_range(0..400) {
        let roll = rng.random_range(0..100);
        if roll < 40 || vertices < 3 {
            let coordinate = |rng: &mut ChaCha8Rng| -> String {
                let x: f64 = rng.random_range(-1e3..1e3);
                match rng.random_range(0..5) {
                    0 => format!("{x}"),
                    1 => format!("{x:.4}"),
                    2 => format!("{x:e}"),
                    3 => format!("{}", x.round() as i64),
                    _ => format!("{:.2}", x * 1e-7),
                }
            };
            let xyz: Vec<String> = (0..3).map(|_| coordinate(rng)).collect();
            text += &format!("v {}{newline}", xyz.join(" "));
            vertices += 1;
        } else if roll < 80 {
            let n = rng.random_range(3..=6);
            let style = rng.random_range(0..4);
            let mut words = Vec::new();
            for _ in 0..n {
                let reference = |rng: &mut ChaCha8Rng, count: i64| {
                    let k = rng.random_range(1..=count.max(1));
                    if rng.random_bool(0.3) {
                        -k
                    } else {
                        count + 1 - k
                    }
                };
                let v = reference(rng, vertices);
                let t = reference(rng, texcoords);
                let m = reference(rng, normals);
                words.push(match style {
                    1 if texcoords > 0 => format!("{v}/{t}"),
                    2 if normals > 0 => format!("{v}//{m}"),
                    3 if texcoords > 0 && normals > 0 => format!("{v}/{t}/{m}"),
                    _ => format!("{v}"),
                });
            }
            text += &format!("f {}{newline}", words.join(" "));
        } else if roll < 85 {
            text += &format!("vt 0.{} 0.5{newline}", rng.random_range(0..1000));
            texcoords += 1;
        } else if roll < 90 {
            text += &format!("vn 0 0 1{newline}");
            normals += 1;
        } else if roll < 94 {
            let tag = if rng.random_bool(0.5) { "o" } else { "g" };
            text += &format!("{tag} part{}{newline}", rng.random_range(0..9));
        } else if roll < 97 {
            text += &format!("# comment {roll}{newline}");
        } else {
            text += newline;
        }
    }
    text
}

#[test]
fn random_plain_files_in_any_number_of_pieces_read_as_tobj_reads_them() {
    let mut rng = ChaCha8Rng::seed_from_u64(2026);
    for _ in 0..300 {
        let text = random_plain_obj(&mut rng);
        for pieces in [1, 2, 3, 5, 16] {
            assert!(
                agrees_with_tobj(text.as_bytes(), pieces),
                "not plain:\n{text}"
            );
        }
    }
}

#[test]
fn random_damage_never_gives_other_triangles_than_tobj() {
    // Bytes overwritten, inserted or removed at random: the plain reader either
    // declines or agrees with tobj, which must then read the file without an error.
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let alphabet = b"vfotg/-+.e0123456789 \n\r\t#\xc3\xa9";
    let (mut declined, mut taken) = (0, 0);
    for _ in 0..400 {
        let mut bytes = random_plain_obj(&mut rng).into_bytes();
        for _ in 0..rng.random_range(1..4) {
            if bytes.is_empty() {
                break;
            }
            let at = rng.random_range(0..bytes.len());
            let byte = alphabet[rng.random_range(0..alphabet.len())];
            match rng.random_range(0..3) {
                0 => bytes[at] = byte,
                1 => bytes.insert(at, byte),
                _ => {
                    bytes.remove(at);
                }
            }
        }
        let pieces = rng.random_range(1..5);
        if agrees_with_tobj(&bytes, pieces) {
            taken += 1;
        } else {
            declined += 1;
        }
    }
    // Both sides are exercised.
    assert!(
        taken > 50 && declined > 50,
        "taken {taken}, declined {declined}"
    );
}

#[test]
fn the_fast_lines_read_as_the_general_path_reads_them() {
    // Pieces of random plain files, damaged or not, and lines at the edges of the
    // fast path's spellings: the same piece (or the same refusal) either way.
    use super::chunk::{parse_chunk, parse_chunk_general};
    let mut rng = ChaCha8Rng::seed_from_u64(41);
    let alphabet = b"vf/-+.e0123456789 \n\r\t\x0b";
    let edge_lines: Vec<String> = [
        "v 1 2 3\nv -0 0.5 -997.1751\nv 1234567890123456789 1 2\nv 12345678901234567890 1 2\n",
        "v 9007199254740992 9007199254740993 0.9007199254740993\nv 1.0000000000000000000001 1 1\n",
        "v 1. .5 1\nv 1 2 3 4\nv 1 2\nv 1e3 2 3\nv +1 2 3\nv 1 2 3\r\nv\t1\t2\t3\x0c\n",
        "f 1 2 3\nf 1/2 2/3 3/4\nf 1//2 2//3 3//4\nf 1/2/3 2/3/4 3/4/5 4/5/6\n",
        "f 1/2/3/ 2 3\nf 1/ 2// 3/4/\nf 0 1 2\nf 1 2\nf 1 2 -1\nf 1234567890 1 2\n",
        "f 123456789 1 2\nf 1/0 2 3\nf 1/-1 2 3\nf 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17\n",
        "f 3 2 1",
    ]
    .iter()
    .flat_map(|t| t.split_inclusive('\n'))
    .map(String::from)
    .collect();
    // Each line on its own, after enough vertices, texture coordinates and normals
    // (and a non-ASCII comment: the fast path reads lines of any piece).
    let before = "# π\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n";
    let mut texts: Vec<Vec<u8>> = edge_lines
        .iter()
        .map(|line| format!("{before}{line}").into_bytes())
        .collect();
    for _ in 0..300 {
        let mut bytes = random_plain_obj(&mut rng).into_bytes();
        if rng.random_bool(0.5) {
            for _ in 0..rng.random_range(1..6) {
                if bytes.is_empty() {
                    break;
                }
                let at = rng.random_range(0..bytes.len());
                bytes[at] = alphabet[rng.random_range(0..alphabet.len())];
            }
        }
        texts.push(bytes);
    }
    let (mut same, mut refused) = (0, 0);
    for text in &texts {
        let fast = parse_chunk(text);
        assert_eq!(
            fast,
            parse_chunk_general(text),
            "{}",
            String::from_utf8_lossy(text)
        );
        match fast {
            Some(chunk) if !chunk.corners.is_empty() => same += 1,
            Some(_) => {}
            None => refused += 1,
        }
    }
    assert!(same > 120 && refused > 20, "read {same}, refused {refused}");
}
