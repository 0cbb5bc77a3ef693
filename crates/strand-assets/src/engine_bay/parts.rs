//! The parts of the engine compartment, designed in mm and built in m.

use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};

use crate::{TriangleMesh, axis_box, chamfered_box, cylinder, tube};

/// One OBJ file of the engine bay: named objects in m.
#[derive(Clone, Debug)]
pub struct Part {
    /// File name in the assets directory (e.g. `radiator.obj`).
    pub file: &'static str,
    /// One line saying what the part is (written as the file's first comment).
    pub description: &'static str,
    /// Named closed meshes, in m.
    pub objects: Vec<(&'static str, TriangleMesh)>,
}

/// mm → m.
fn mm(x: f64) -> f64 {
    x / 1000.0
}

fn mm_point(x: f64, y: f64, z: f64) -> Point3<f64> {
    Point3::new(mm(x), mm(y), mm(z))
}

/// Axis box between two corners given in mm.
fn box_mm(min: [f64; 3], max: [f64; 3]) -> TriangleMesh {
    axis_box(
        mm_point(min[0], min[1], min[2]),
        mm_point(max[0], max[1], max[2]),
    )
}

/// Chamfered box between two corners given in mm, chamfer in mm.
fn chamfered_mm(min: [f64; 3], max: [f64; 3], chamfer: f64) -> TriangleMesh {
    chamfered_box(
        mm_point(min[0], min[1], min[2]),
        mm_point(max[0], max[1], max[2]),
        mm(chamfer),
    )
}

/// A mesh built along z, turned so local z points along world +x (local +x goes to
/// world −z, so a polygon vertex sits at the bottom), then centred at `centre` (mm).
fn along_x(mesh: TriangleMesh, centre: [f64; 3]) -> TriangleMesh {
    let turn = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
    let at = Translation3::new(mm(centre[0]), mm(centre[1]), mm(centre[2]));
    mesh.transformed(&Isometry3::from_parts(at, turn))
}

/// The oil cooler: a 150 × 100 × 40 mm plate cooler whose large face is normal to
/// the nozzle direction (1, 1, −1)/√3, 25 mm behind the `oil_cooler` connector at
/// (−40, −190, 75) mm; its long side is horizontal.
fn oil_cooler() -> TriangleMesh {
    let d = Vector3::new(1.0, 1.0, -1.0).normalize();
    let u = Vector3::new(1.0, -1.0, 0.0).normalize();
    let v = d.cross(&u);
    let rotation = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[u, v, d]));
    let connector = mm_point(-40.0, -190.0, 75.0);
    let centre = connector - d * mm(25.0 + 20.0);
    let local = axis_box(mm_point(-75.0, -50.0, -20.0), mm_point(75.0, 50.0, 20.0));
    local.transformed(&Isometry3::from_parts(
        Translation3::from(centre.coords),
        UnitQuaternion::from_rotation_matrix(&rotation),
    ))
}

/// All parts of the engine compartment (see the module documentation for the
/// layout and the designed contacts). Sizes in the comments are mm.
pub fn parts() -> Vec<Part> {
    vec![
        Part {
            file: "radiator.obj",
            description: "radiator: 30 mm core 540 x 380 mm, two end tanks, outlet boss on the left tank",
            objects: vec![
                (
                    "core",
                    box_mm([-260.0, -300.0, 100.0], [-230.0, 240.0, 480.0]),
                ),
                (
                    "left_tank",
                    chamfered_mm([-268.0, 240.0, 90.0], [-222.0, 300.0, 490.0], 6.0),
                ),
                (
                    "right_tank",
                    chamfered_mm([-268.0, -360.0, 90.0], [-222.0, -300.0, 490.0], 6.0),
                ),
                // radiator_outlet (-180, 215, 200) points -y: the face y = 245 is 30 mm behind it.
                (
                    "outlet_boss",
                    box_mm([-222.0, 245.0, 170.0], [-150.0, 290.0, 230.0]),
                ),
            ],
        },
        Part {
            file: "fan_shroud.obj",
            description: "fan shroud: ring 296 mm outer diameter, 50 mm deep, behind the right half of the radiator, with the fan hub",
            objects: vec![
                (
                    "shroud_ring",
                    along_x(
                        tube(mm(140.0), mm(148.0), mm(50.0), 64),
                        [-195.0, -110.0, 300.0],
                    ),
                ),
                (
                    "fan_hub",
                    along_x(
                        cylinder(mm(45.0), mm(40.0), 32, true),
                        [-195.0, -110.0, 300.0],
                    ),
                ),
            ],
        },
        Part {
            file: "engine.obj",
            description: "engine: block 480 x 590 x 540 mm with 25 mm chamfers, water-pump housing (120 mm diameter) at its front",
            objects: vec![
                (
                    "block",
                    chamfered_mm([140.0, -260.0, -160.0], [620.0, 330.0, 380.0], 25.0),
                ),
                // engine_stub (80, 265, 60) points -z: the housing's bottom line z = 90 is 30 mm above it.
                (
                    "water_pump",
                    along_x(
                        cylinder(mm(60.0), mm(100.0), 48, true),
                        [90.0, 265.0, 150.0],
                    ),
                ),
            ],
        },
        Part {
            file: "oil_cooler.obj",
            description: "oil cooler: 150 x 100 x 40 mm plate cooler, face normal to the oil_cooler nozzle, 25 mm behind it",
            objects: vec![("cooler", oil_cooler())],
        },
        Part {
            file: "brackets.obj",
            description: "brackets: engine-mount arm under hose 3 (hose 3 rests on it), front cross member",
            objects: vec![
                // Top z = -77: 10 mm above the bottom of hose 3 solved without contact.
                (
                    "hose3_support",
                    box_mm([20.0, 96.0, -117.0], [140.0, 126.0, -77.0]),
                ),
                (
                    "cross_member",
                    box_mm([-60.0, -380.0, -260.0], [40.0, 380.0, -200.0]),
                ),
            ],
        },
    ]
}
