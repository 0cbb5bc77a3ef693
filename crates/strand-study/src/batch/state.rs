//! The files of one variant besides its results: `state.json`, the solved state bit
//! for bit (so a resumed batch warm-starts the next variant exactly as an
//! uninterrupted one would), and `failed.json`, why a variant has no result.
//!
//! `state.json` carries two checksums (FNV-1a, [`super::checksum`]): `checksum`, over
//! its own numbers, and `result_json`, over the exact bytes of the variant's
//! `result.json`. A resumed batch checks both ([`super::integrity`]), so a truncated
//! or altered file of either kind is found and the variant solved again.

use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};
use strand_rod::RodState;
use strand_system::{JointState, Pose, SystemState};

use super::checksum::{Fnv, fnv1a_words, matches_checksum};

/// A [`SystemState`] as the IEEE-754 bit patterns of its numbers (exact in JSON).
#[derive(Debug, Serialize, Deserialize)]
pub(crate) struct StoredState {
    /// Per rod: positions (x, y, z per vertex) and frames (w, i, j, k per edge).
    rods: Vec<(Vec<u64>, Vec<u64>)>,
    /// Per body: position (3) and orientation (w, i, j, k).
    bodies: Vec<[u64; 7]>,
    /// Per clip: value and rotation (w, i, j, k).
    clips: Vec<[u64; 5]>,
    /// Checksum of the bytes of the variant's `result.json`: word-wise FNV-1a
    /// (`w…`, [`super::checksum::fnv1a_words`]), byte-wise in files of earlier
    /// versions (16 hex digits), absent in files written before checksums existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    result_json: Option<String>,
    /// FNV-1a of the numbers above and `result_json` ([`StoredState::digest`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    checksum: Option<String>,
}

/// Why a stored state or result does not pass its checksums.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub(crate) enum ChecksumError {
    /// `state.json`'s own numbers do not match its `checksum`.
    #[error("its checksum does not match its content")]
    State,
    /// `result.json` is not the file `state.json` was written with.
    #[error("its checksum does not match the one recorded in state.json")]
    Result,
}

fn bits(values: &[f64]) -> Vec<u64> {
    values.iter().map(|x| x.to_bits()).collect()
}

fn quaternion(b: &[u64]) -> UnitQuaternion<f64> {
    let f = |k: usize| f64::from_bits(b[k]);
    UnitQuaternion::new_unchecked(Quaternion::new(f(0), f(1), f(2), f(3)))
}

impl StoredState {
    /// The exact bit patterns of `state`, with the checksum of `result_json` (the
    /// bytes of the `result.json` written with it) and its own.
    pub(crate) fn from_state(state: &SystemState, result_json: &[u8]) -> Self {
        let q = |q: &UnitQuaternion<f64>| [q.w, q.i, q.j, q.k];
        let mut stored = Self {
            rods: state
                .rods
                .iter()
                .map(|r| {
                    let p: Vec<f64> = r.positions.iter().flat_map(|v| [v.x, v.y, v.z]).collect();
                    let f: Vec<f64> = r.frames.iter().flat_map(q).collect();
                    (bits(&p), bits(&f))
                })
                .collect(),
            bodies: state
                .bodies
                .iter()
                .map(|b| {
                    let [w, i, j, k] = q(&b.orientation);
                    [b.position.x, b.position.y, b.position.z, w, i, j, k].map(f64::to_bits)
                })
                .collect(),
            clips: state
                .clips
                .iter()
                .map(|c| {
                    let [w, i, j, k] = q(&c.rotation);
                    [c.value, w, i, j, k].map(f64::to_bits)
                })
                .collect(),
            result_json: Some(fnv1a_words(result_json)),
            checksum: None,
        };
        stored.checksum = Some(stored.digest());
        stored
    }

    /// FNV-1a over every number (with the list lengths) and `result_json`.
    fn digest(&self) -> String {
        let mut h = Fnv::default();
        h.word(self.rods.len() as u64);
        for (p, f) in &self.rods {
            h.word(p.len() as u64);
            p.iter().for_each(|w| _ = h.word(*w));
            h.word(f.len() as u64);
            f.iter().for_each(|w| _ = h.word(*w));
        }
        h.word(self.bodies.len() as u64);
        self.bodies.iter().flatten().for_each(|w| _ = h.word(*w));
        h.word(self.clips.len() as u64);
        self.clips.iter().flatten().for_each(|w| _ = h.word(*w));
        h.bytes(self.result_json.as_deref().unwrap_or("").as_bytes());
        h.hex()
    }

    /// Checks the state's own checksum and, when `result_json` (the bytes of the
    /// variant's `result.json`) is given, that it is the file written with it. A
    /// state without checksums (an older batch) passes.
    pub(crate) fn verify(&self, result_json: Option<&[u8]>) -> Result<(), ChecksumError> {
        if self.checksum.as_ref().is_some_and(|c| *c != self.digest()) {
            return Err(ChecksumError::State);
        }
        match (&self.result_json, result_json) {
            (Some(recorded), Some(bytes)) if !matches_checksum(recorded, bytes) => {
                Err(ChecksumError::Result)
            }
            _ => Ok(()),
        }
    }

    /// Whether the file carries checksums (written by this version).
    pub(crate) fn has_checksums(&self) -> bool {
        self.checksum.is_some() && self.result_json.is_some()
    }

    /// The state back, if its shape fits `like` (a state of the same model).
    pub(crate) fn to_state(&self, like: &SystemState) -> Option<SystemState> {
        let fits = self.rods.len() == like.rods.len()
            && self.bodies.len() == like.bodies.len()
            && self.clips.len() == like.clips.len()
            && self.rods.iter().zip(&like.rods).all(|((p, f), r)| {
                p.len() == 3 * r.positions.len() && f.len() == 4 * r.frames.len()
            });
        if !fits {
            return None;
        }
        let rods = self
            .rods
            .iter()
            .map(|(p, f)| {
                let positions = p
                    .chunks_exact(3)
                    .map(|c| {
                        Vector3::new(
                            f64::from_bits(c[0]),
                            f64::from_bits(c[1]),
                            f64::from_bits(c[2]),
                        )
                    })
                    .collect();
                let frames = f.chunks_exact(4).map(quaternion).collect();
                RodState::new(positions, frames)
            })
            .collect();
        let bodies = self
            .bodies
            .iter()
            .map(|b| Pose {
                position: Vector3::new(
                    f64::from_bits(b[0]),
                    f64::from_bits(b[1]),
                    f64::from_bits(b[2]),
                ),
                orientation: quaternion(&b[3..]),
            })
            .collect();
        let clips = self
            .clips
            .iter()
            .map(|c| JointState {
                value: f64::from_bits(c[0]),
                rotation: quaternion(&c[1..]),
            })
            .collect();
        Some(SystemState {
            rods,
            bodies,
            clips,
        })
    }
}

/// `failed.json`: a variant without a converged result, and why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FailedVariant {
    /// The variant's id.
    pub id: String,
    /// `"build"` (the changed case is invalid, e.g. a hose shorter than the distance
    /// of its ends) or `"solve"` (the solver did not converge).
    pub stage: String,
    /// The reason, as a sentence.
    pub reason: String,
    /// Residual of the last iterate, N (solve failures).
    #[serde(
        rename = "residual_N",
        default,
        skip_serializing_if = "Option::is_none"
    )]
    pub residual_n: Option<f64>,
    /// Newton iterations spent (solve failures).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub iterations: Option<usize>,
    /// Whether the solve started from a neighbour's solution.
    #[serde(default)]
    pub warm_start: bool,
    /// Wall-clock time spent on the variant, s.
    #[serde(rename = "time_s", default)]
    pub time_s: f64,
}
