//! A solved [`SystemState`] as plain numbers for pickling (Python floats are IEEE
//! doubles, so the state comes back bit for bit): per rod the vertex positions
//! (x, y, z per vertex, m) and edge frames (w, i, j, k per edge), per body position
//! (m) and orientation, per clip its joint value and rotation.

use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use strand_rod::RodState;
use strand_system::{JointState, Pose, SystemState};

/// The numbers of a state: rods (positions, frames), bodies, clips.
pub type StateData = (Vec<(Vec<f64>, Vec<f64>)>, Vec<[f64; 7]>, Vec<[f64; 5]>);

fn wxyz(q: &UnitQuaternion<f64>) -> [f64; 4] {
    [q.w, q.i, q.j, q.k]
}

fn unit(c: &[f64]) -> UnitQuaternion<f64> {
    UnitQuaternion::new_unchecked(Quaternion::new(c[0], c[1], c[2], c[3]))
}

/// The numbers of `state`.
pub fn to_data(state: &SystemState) -> StateData {
    let rods = state
        .rods
        .iter()
        .map(|r| {
            let p = r.positions.iter().flat_map(|v| [v.x, v.y, v.z]).collect();
            let f = r.frames.iter().flat_map(wxyz).collect();
            (p, f)
        })
        .collect();
    let bodies = state
        .bodies
        .iter()
        .map(|b| {
            let [w, i, j, k] = wxyz(&b.orientation);
            [b.position.x, b.position.y, b.position.z, w, i, j, k]
        })
        .collect();
    let clips = state
        .clips
        .iter()
        .map(|c| {
            let [w, i, j, k] = wxyz(&c.rotation);
            [c.value, w, i, j, k]
        })
        .collect();
    (rods, bodies, clips)
}

/// The state of `data` (`None` when a rod's lists are not whole vertices/frames).
pub fn from_data(data: &StateData) -> Option<SystemState> {
    let (rods, bodies, clips) = data;
    let rods = rods
        .iter()
        .map(|(p, f)| {
            (p.len() % 3 == 0 && f.len() % 4 == 0).then(|| {
                let positions = p
                    .chunks_exact(3)
                    .map(|c| Vector3::new(c[0], c[1], c[2]))
                    .collect();
                RodState::new(positions, f.chunks_exact(4).map(unit).collect())
            })
        })
        .collect::<Option<Vec<_>>>()?;
    let bodies = bodies
        .iter()
        .map(|b| Pose {
            position: Vector3::new(b[0], b[1], b[2]),
            orientation: unit(&b[3..]),
        })
        .collect();
    let clips = clips
        .iter()
        .map(|c| JointState {
            value: c[0],
            rotation: unit(&c[1..]),
        })
        .collect();
    Some(SystemState {
        rods,
        bodies,
        clips,
    })
}
