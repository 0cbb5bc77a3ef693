//! `--vary` parsing, ids, the warm-start tree and the shard split.

use strand_case::Case;
use strand_case::schema::{Amount, Change};

use super::plan::Plan;
use super::spec::{Vary, parse_shard};

fn cooler() -> Case {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases/cooler_hose.ron");
    Case::from_path(path).unwrap()
}

fn vary(text: &str) -> Vary {
    Vary::parse(text, &cooler().file).unwrap_or_else(|e| panic!("{text}: {e}"))
}

fn error(text: &str) -> String {
    match Vary::parse(text, &cooler().file) {
        Ok(v) => panic!("{text}: expected an error, got {v:?}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn ranges_offsets_units_and_ids() {
    let v = vary("hose2.length=+0mm..+100mm:10mm");
    assert_eq!(v.item, "rods.hose2.length");
    assert!(v.offset);
    assert_eq!(
        v.values,
        (0..=10).map(|k| 10.0 * k as f64).collect::<Vec<_>>()
    );
    assert_eq!(v.id_part(3), "hose2.length_p30mm");
    assert_eq!(v.value_text(3), "+30mm");
    assert_eq!(v.change(3).change, Change::Add(Amount::Number(30.0)));
    assert_eq!(v.anchor(), 0);
    // Metres in a case written in mm; a downward range; a negative offset.
    let v = vary("rods.hose2.length=+0.05m..-0.05m:0.025m");
    assert_eq!(v.values, [0.05, 0.025, 0.0, -0.025, -0.05]);
    assert_eq!(v.id_part(4), "rods.hose2.length_m0.05m");
    assert_eq!(v.change(0).change, Change::Add(Amount::Number(50.0)));
    assert_eq!(v.anchor(), 2);
    // Decimal steps land on their decimal values.
    let v = vary("hose2.length=+0..+0.3:0.1");
    assert_eq!(v.values, [0.0, 0.1, 0.2, 0.3]);
    assert_eq!(v.unit, "mm");
    // Values (Set) anchor at the value nearest the case's own (190 mm).
    let v = vary("hose2.length=150mm,180mm,250mm");
    assert!(!v.offset);
    assert_eq!(v.change(1).change, Change::Set(Amount::Number(180.0)));
    assert_eq!(v.anchor(), 1);
    // Grams become kg; vector components become vectors.
    let v = vary("tee.mass=500g,1500g");
    assert_eq!(v.item, "junctions.tee.mass");
    assert_eq!(v.change(0).change, Change::Set(Amount::Number(0.5)));
    assert_eq!(v.anchor(), 0);
    let v = vary("oil_cooler.position.z=-10mm,+10mm");
    assert_eq!(v.item, "connectors.oil_cooler.position");
    assert_eq!(
        v.change(1).change,
        Change::Add(Amount::Vector([0.0, 0.0, 10.0]))
    );
    let v = vary("gravity.z=+0..+2:1");
    assert_eq!(
        v.change(2).change,
        Change::Add(Amount::Vector([0.0, 0.0, 2.0]))
    );
    assert_eq!(v.id_part(2), "gravity.z_p2m_s2");
}

#[test]
fn directions_turn_in_degrees_and_stiffnesses_take_their_units() {
    let v = vary("oil_cooler.direction.z=-10deg..+10deg:5deg");
    assert_eq!(v.item, "connectors.oil_cooler.direction");
    assert_eq!((v.component, v.unit.as_str()), (Some(2), "deg"));
    assert_eq!(v.values, [-10.0, -5.0, 0.0, 5.0, 10.0]);
    assert_eq!(
        v.change(0).change,
        Change::Add(Amount::Vector([0.0, 0.0, -10.0]))
    );
    // Radians are turned into degrees for the case.
    let r = vary("tee.ports.hose2.direction.x=+0.1rad");
    assert_eq!(r.item, "junctions.tee.ports.hose2.direction");
    let Change::Add(Amount::Vector(turn)) = r.change(0).change else {
        panic!("an offset vector")
    };
    assert!((turn[0] - 0.1 * 180.0 / std::f64::consts::PI).abs() < 1e-12);
    // A modulus in MPa is set in Pa; the default unit is Pa.
    let e = vary("hose_small.youngs_modulus=4MPa,6MPa");
    assert_eq!(e.item, "sections.hose_small.youngs_modulus");
    assert_eq!(e.change(1).change, Change::Set(Amount::Number(6e6)));
    assert_eq!(vary("hose_small.youngs_modulus=+1e5").unit, "Pa");
    // A turn is an offset; a tube has no `ei`.
    let m = error("oil_cooler.direction.z=10deg");
    assert!(m.contains("can only be offset"), "{m}");
    let m = error("hose_small.ei=+1");
    assert!(
        m.contains("not an item a batch can vary") && m.contains("it is a Tube"),
        "{m}"
    );
    // Every variant of a direction and a modulus builds.
    let case = cooler();
    for change in [v.change(4), r.change(0), e.change(0)] {
        case.build_with_changes("t", &[change], None).unwrap();
    }
}

#[test]
fn bad_varies_say_what_to_write() {
    for (text, needle) in [
        ("hose2.length", "missing '='"),
        (
            "hose9.length=+0..+1:1",
            "names no rod, junction or connector",
        ),
        ("hose2.colour=+0..+1:1", "not an item a batch can vary"),
        ("hose2.length=+0mm..+100mm", "a range needs a step"),
        (
            "hose2.length=+0mm..+100mm:30mm",
            "not a whole number of steps",
        ),
        ("hose2.length=+0mm..+100mm:0mm", "step must be > 0"),
        ("hose2.length=-50mm..50mm:10mm", "some values have a sign"),
        ("hose2.length=+10kg", "not a number with a unit"),
        ("oil_cooler.position=+0..+1:1", "is a vector"),
        ("oil_cooler.position.z=10", "can only be offset"),
        ("hose2.segments=+10", "can only be set"),
        ("hose2.segments=2.5", "whole number"),
        ("hose2.length=+1mm,+1mm", "appears twice"),
    ] {
        let m = error(text);
        assert!(m.contains(needle), "{text}: {m}");
        assert!(
            m.starts_with(&format!("--vary {text}: ")) && m.contains("hint: "),
            "{m}"
        );
    }
    assert_eq!(parse_shard("2/4"), Ok((2, 4)));
    for bad in ["0/4", "5/4", "1", "a/b", "1/0"] {
        assert!(parse_shard(bad).is_err(), "{bad}");
    }
}

/// The variant of `plan` with the given value indices.
fn at(plan: &Plan, index: &[usize]) -> usize {
    plan.variants.iter().position(|v| v.index == index).unwrap()
}

#[test]
fn the_tree_walks_each_line_away_from_the_case_in_single_steps() {
    let plan = Plan::new(vec![
        vary("hose2.length=-20mm..+20mm:10mm"),
        vary("tee.mass=0.5kg,1kg,1.5kg"),
    ])
    .unwrap();
    assert_eq!(plan.variants.len(), 15);
    assert_eq!(
        plan.variants[at(&plan, &[3, 2])].id,
        "hose2.length_p10mm__tee.mass_1.5kg"
    );
    // The root is at the anchors (+0 mm, the case's 1 kg).
    assert_eq!(plan.roots, [at(&plan, &[2, 1])]);
    for v in &plan.variants {
        let Some(p) = v.parent else { continue };
        let up = &plan.variants[p].index;
        // One step in one parameter, towards the anchor, in the last one off-anchor.
        let moved: Vec<usize> = (0..2).filter(|&d| up[d] != v.index[d]).collect();
        assert_eq!(moved.len(), 1, "{}", v.id);
        let d = moved[0];
        let anchor = [2, 1][d];
        assert_eq!(
            v.index[d].abs_diff(anchor),
            up[d].abs_diff(anchor) + 1,
            "{}",
            v.id
        );
        assert!((d + 1..2).all(|e| v.index[e] == [2, 1][e]), "{}", v.id);
    }
    // Depth-first order: every variant exactly once, parents first.
    let mut seen = [false; 15];
    for &n in &plan.order {
        assert!(plan.variants[n].parent.is_none_or(|p| seen[p]));
        seen[n] = true;
    }
    assert!(seen.iter().all(|s| *s));
    // Line samples: the ancestors on the same line, nearest first.
    let (samples, x) = plan.line_samples(at(&plan, &[2, 2]), 3);
    assert_eq!((samples, x), (vec![(at(&plan, &[2, 1]), 1.0)], 1.5));
    let (samples, x) = plan.line_samples(at(&plan, &[4, 0]), 3);
    assert_eq!((samples, x), (vec![(at(&plan, &[4, 1]), 1.0)], 0.5));
    let (samples, x) = plan.line_samples(at(&plan, &[4, 1]), 3);
    let expected = vec![(at(&plan, &[3, 1]), 10.0), (at(&plan, &[2, 1]), 0.0)];
    assert_eq!((samples, x), (expected, 20.0));
}

#[test]
fn shards_cover_every_variant_once_and_include_their_ancestors() {
    let plan = Plan::new(vec![
        vary("hose2.length=+0mm..+90mm:10mm"),
        vary("tee.mass=0.5kg,1kg"),
    ])
    .unwrap();
    for n in 1..=7 {
        let mut count = vec![0; plan.variants.len()];
        for i in 1..=n {
            let owned = plan.owned(Some((i, n)));
            let needed = plan.needed(&owned);
            for (v, o) in owned.iter().enumerate() {
                if *o {
                    count[v] += 1;
                    let mut up = plan.variants[v].parent;
                    while let Some(p) = up {
                        assert!(needed[p]);
                        up = plan.variants[p].parent;
                    }
                }
            }
        }
        assert!(count.iter().all(|c| *c == 1), "{n} shards: {count:?}");
    }
    assert!(plan.owned(None).iter().all(|o| *o));
}

/// The progress callback hears of every owned variant exactly once, with running
/// counts, and a resumed run reports the same variants as skipped; a variant whose
/// changed case does not build is a failure in the report, not an error.
#[test]
fn progress_reports_each_variant_once_and_resume_skips_them() {
    use std::sync::Mutex;

    use super::{Batch, BatchSpec, Progress};

    let case =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases/elastica_fig2.ron");
    let dir = tempfile::tempdir().unwrap();
    // -900 mm leaves the rod shorter than the distance between its held ends.
    let spec = BatchSpec {
        vary: vec!["rod.length=+0mm,+10mm,-900mm".into()],
        segments: Some(6),
        jobs: Some(2),
        ..BatchSpec::new(&case, dir.path())
    };
    let run = |spec: &BatchSpec| {
        let heard = Mutex::new(Vec::<Progress>::new());
        let report = Batch::plan(spec.clone())
            .unwrap()
            .run(&|p| heard.lock().unwrap().push(p))
            .unwrap();
        (report, heard.into_inner().unwrap())
    };
    let (report, heard) = run(&spec);
    assert_eq!(
        (
            report.counts.computed,
            report.counts.skipped,
            report.counts.failed
        ),
        (3, 0, 1)
    );
    let mut done: Vec<usize> = heard.iter().map(|p| p.done).collect();
    done.sort_unstable();
    assert_eq!(done, [1, 2, 3]);
    assert!(heard.iter().all(|p| p.total == 3));
    let mut ids: Vec<&str> = heard.iter().map(|p| p.id.as_str()).collect();
    ids.sort_unstable();
    assert_eq!(
        ids,
        ["rod.length_m900mm", "rod.length_p0mm", "rod.length_p10mm"]
    );
    let failed: Vec<&Progress> = heard.iter().filter(|p| p.failed_now).collect();
    assert_eq!(failed.len(), 1);
    assert_eq!(failed[0].id, "rod.length_m900mm");
    assert_eq!(heard.iter().map(|p| p.failed).max(), Some(1));
    assert_eq!(report.failures.len(), 1);
    assert_eq!(report.failures[0].stage, "build");
    assert!(report.summary.is_some());
    // The summary, made from what the run kept in memory of the results it wrote, is
    // the one made from the files (full results read back).
    let summary = std::fs::read_to_string(dir.path().join("summary.csv")).unwrap();
    let files = super::read_batch(dir.path()).unwrap();
    assert_eq!(
        summary,
        super::summary_csv(&files.manifest, &files.outcomes)
    );
    // Resumed: nothing solved again, every variant heard of once more.
    let (again, heard) = run(&spec);
    assert_eq!(
        (
            again.counts.computed,
            again.counts.skipped,
            again.counts.failed
        ),
        (0, 3, 1)
    );
    assert_eq!(heard.len(), 3);
    assert_eq!(heard.iter().filter(|p| p.failed_now).count(), 1);
    // The resumed run reads every result back (thinned): the same summary.
    assert_eq!(
        std::fs::read_to_string(dir.path().join("summary.csv")).unwrap(),
        summary
    );
}
