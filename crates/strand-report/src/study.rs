//! Variant studies: peak internal force and moment per rod per variant, with the change
//! against the first (reference) variant, as a CSV table; the curves themselves are
//! plotted by [`crate::study_svg`].

use strand_system::{Model, Support};

use crate::number::push_number;
use crate::result::{ResultDoc, RodResult};

/// Where the arc length of a rod's curves is measured from in a study.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum ArcOrigin {
    /// `s = 0` at the rod's start (vertex 0): `s` is the reference arc length `s_m`.
    Start,
    /// `s = 0` at the rod's end (vertex N): `s = L − s_m`.
    End,
}

impl ArcOrigin {
    /// Arc length from this origin of the vertex at reference arc length `s` (m) of a
    /// rod of reference length `length` (m).
    pub fn measure(self, s: f64, length: f64) -> f64 {
        match self {
            ArcOrigin::Start => s,
            ArcOrigin::End => length - s,
        }
    }
}

/// The origin of arc length for rod `rod` of `model` in study plots and tables: the
/// end attached to a junction port if exactly one end is (so that the curves of the
/// hoses of a junction all start there, as in the paper's Fig. 7), otherwise the
/// rod's start.
pub fn arc_origin(model: &Model, rod: usize) -> ArcOrigin {
    let spec = &model.system().rods[rod];
    let at_port = |support: Support| matches!(support, Support::Port { .. });
    match (at_port(spec.start.support), at_port(spec.end.support)) {
        (false, true) => ArcOrigin::End,
        _ => ArcOrigin::Start,
    }
}

/// One variant's results in a study.
#[derive(Clone, Copy, Debug)]
pub struct StudyRun<'a> {
    /// The variant's name (`base` for the case itself).
    pub variant: &'a str,
    /// Its results.
    pub doc: &'a ResultDoc,
}

/// The peaks of one rod in one variant.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StudyPeak {
    /// Variant name.
    pub variant: String,
    /// Rod name.
    pub rod: String,
    /// Largest `|f̄_j|` over the vertices (`force_N` in `result.json`), N.
    pub peak_force_n: f64,
    /// Arc length (from the rod's [`ArcOrigin`]) where it occurs, m.
    pub peak_force_s_m: f64,
    /// Largest `|m_j|` over the vertices (`moment_Nm` in `result.json`), N·m.
    pub peak_moment_nm: f64,
    /// Arc length (from the rod's [`ArcOrigin`]) where it occurs, m.
    pub peak_moment_s_m: f64,
    /// Change of the peak force against the same rod in the first variant, %
    /// (`None` where that is zero or the rod is missing there).
    pub force_change_pct: Option<f64>,
    /// Change of the peak moment against the same rod in the first variant, %.
    pub moment_change_pct: Option<f64>,
}

/// Euclidean norm of a vector written as `[x, y, z]`.
pub fn magnitude(v: &[f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// The largest magnitude in `values` and its vertex (the first on ties); NaN wins, so
/// that a non-finite result is not hidden.
pub(crate) fn peak(values: &[[f64; 3]]) -> (f64, usize) {
    let mut best = (f64::NEG_INFINITY, 0);
    for (j, v) in values.iter().enumerate() {
        let m = magnitude(v);
        if m > best.0 || m.is_nan() && !best.0.is_nan() {
            best = (m, j);
        }
    }
    if values.is_empty() { (0.0, 0) } else { best }
}

fn change(value: f64, reference: Option<f64>) -> Option<f64> {
    reference
        .filter(|r| *r != 0.0 && r.is_finite())
        .map(|r| 100.0 * (value - r) / r)
}

/// The origin for rod `index` named `name` (by index; [`ArcOrigin::Start`] beyond).
pub(crate) fn origin_of(origins: &[ArcOrigin], index: usize) -> ArcOrigin {
    origins.get(index).copied().unwrap_or(ArcOrigin::Start)
}

/// Arc length of vertex `j` of `rod` from its origin, m.
pub(crate) fn arc(rod: &RodResult, origin: ArcOrigin, j: usize) -> f64 {
    origin.measure(rod.s_m[j], rod.length_m)
}

/// Peaks per rod per variant, in the order of `runs` and of their rods; `origins[r]`
/// is the arc-length origin of rod `r`. The changes are against the first run.
pub fn study_peaks(runs: &[StudyRun], origins: &[ArcOrigin]) -> Vec<StudyPeak> {
    let mut peaks: Vec<StudyPeak> = Vec::new();
    for run in runs {
        for (r, rod) in run.doc.rods.iter().enumerate() {
            let origin = origin_of(origins, r);
            let (force, jf) = peak(&rod.force_n);
            let (moment, jm) = peak(&rod.moment_nm);
            let reference = peaks.iter().find(|p| p.rod == rod.name);
            peaks.push(StudyPeak {
                variant: run.variant.to_string(),
                rod: rod.name.clone(),
                peak_force_n: force,
                peak_force_s_m: arc(rod, origin, jf),
                peak_moment_nm: moment,
                peak_moment_s_m: arc(rod, origin, jm),
                force_change_pct: change(force, reference.map(|p| p.peak_force_n)),
                moment_change_pct: change(moment, reference.map(|p| p.peak_moment_nm)),
            });
        }
    }
    peaks
}

/// Header of `study.csv` (SI units; changes in % against the first variant, empty
/// where undefined).
pub const STUDY_CSV_HEADER: &str = "variant,rod,peak_force_N,peak_force_s_m,peak_moment_Nm,\
peak_moment_s_m,force_change_pct,moment_change_pct";

/// The text of `study.csv`: [`STUDY_CSV_HEADER`] and one row per rod per variant.
pub fn study_csv(peaks: &[StudyPeak]) -> String {
    let mut out = String::from(STUDY_CSV_HEADER);
    out.push('\n');
    for p in peaks {
        out.push_str(&p.variant);
        out.push(',');
        out.push_str(&p.rod);
        for value in [
            Some(p.peak_force_n),
            Some(p.peak_force_s_m),
            Some(p.peak_moment_nm),
            Some(p.peak_moment_s_m),
            p.force_change_pct,
            p.moment_change_pct,
        ] {
            out.push(',');
            if let Some(v) = value {
                push_number(&mut out, v);
            }
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::Timing;
    use crate::tests::sample_rod;

    /// A result document of two rods: `sample_rod` with its forces scaled by `scale`
    /// and a copy named `other` with a moment peak in the middle.
    pub(crate) fn doc(scale: f64) -> ResultDoc {
        let mut a = sample_rod();
        for f in &mut a.force_n {
            *f = f.map(|x| x * scale);
        }
        a.force_n[2] = [0.0, 3.0 * scale, 4.0 * scale];
        let mut b = sample_rod();
        b.name = "other".into();
        b.moment_nm[1] = [0.0, 0.0, -2.0 * scale];
        ResultDoc {
            case: "sample".into(),
            variant: None,
            warm_start: false,
            base_iterations: None,
            converged: true,
            termination: "converged".into(),
            residual_n: 0.0,
            force_residual_n: 0.0,
            moment_residual_nm: 0.0,
            tolerance_n: 1e-9,
            iterations: 1,
            shifted_iterations: 0,
            stable: true,
            negative_directions: 0,
            neutral_directions: 0,
            gauge_freedoms: 0,
            residual_floor_n: 0.0,
            applied_load_n: 0.0,
            fine_iterations: 0,
            coarse_iterations: 0,
            continuation_steps: 0,
            continuation_iterations: 0,
            escape_iterations: 0,
            energy_j: 0.0,
            unknowns: 0,
            timing_s: Timing::default(),
            rods: vec![a, b],
            reactions: Vec::new(),
            bodies: Vec::new(),
            clips: Vec::new(),
            contacts: Vec::new(),
            clearance: Vec::new(),
            environment: Vec::new(),
            findings: Vec::new(),
            provenance: None,
        }
    }

    #[test]
    fn peaks_and_changes_against_the_first_variant() {
        let (base, longer) = (doc(1.0), doc(1.5));
        let runs = [
            StudyRun {
                variant: "base",
                doc: &base,
            },
            StudyRun {
                variant: "longer",
                doc: &longer,
            },
        ];
        let peaks = study_peaks(&runs, &[ArcOrigin::Start, ArcOrigin::End]);
        assert_eq!(peaks.len(), 4);
        let p = &peaks[0];
        assert_eq!((p.variant.as_str(), p.rod.as_str()), ("base", "rod"));
        assert_eq!((p.peak_force_n, p.peak_force_s_m), (5.0, 1.0));
        assert_eq!((p.force_change_pct, p.moment_change_pct), (None, None));
        // The moment of `other` peaks at s_m = 0.5, measured from the end: 0.5.
        assert_eq!(
            (peaks[1].peak_moment_nm, peaks[1].peak_moment_s_m),
            (2.0, 0.5)
        );
        let q = &peaks[2];
        assert_eq!((q.variant.as_str(), q.rod.as_str()), ("longer", "rod"));
        assert!((q.force_change_pct.unwrap() - 50.0).abs() < 1e-12);
        // Zero reference moment: no relative change.
        assert_eq!(q.moment_change_pct, None);
        assert!((peaks[3].moment_change_pct.unwrap() - 50.0).abs() < 1e-12);

        let csv = study_csv(&peaks);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines[0], STUDY_CSV_HEADER);
        assert_eq!(lines.len(), 5);
        assert_eq!(lines[1], "base,rod,5,1,0,0,,");
        assert!(
            lines[3].starts_with("longer,rod,7.5,1,0,0,50,"),
            "{}",
            lines[3]
        );
        assert!(lines.iter().all(|l| l.split(',').count() == 8));
    }

    #[test]
    fn arc_is_measured_from_the_origin() {
        assert_eq!(ArcOrigin::Start.measure(0.25, 1.0), 0.25);
        assert_eq!(ArcOrigin::End.measure(0.25, 1.0), 0.75);
    }
}
