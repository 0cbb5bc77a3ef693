//! Tests of the case files shipped in `cases/` and of the example in `cases/README.md`.

use nalgebra::Vector3;

use crate::Case;

fn cases_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases")
}

#[test]
fn every_shipped_case_builds() {
    let mut count = 0;
    for entry in std::fs::read_dir(cases_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "ron") {
            let built = Case::from_path(&path).and_then(|c| c.build(None));
            assert!(built.is_ok(), "{}: {}", path.display(), built.unwrap_err());
            let case = Case::from_path(&path).unwrap();
            for name in case.variant_names() {
                let built = case.build_variant(name, None);
                assert!(built.is_ok(), "{}: {}", path.display(), built.unwrap_err());
            }
            count += 1;
        }
    }
    assert!(count >= 5, "found only {count} cases");
}

#[test]
fn readme_example_builds() {
    let readme = std::fs::read_to_string(cases_dir().join("README.md")).unwrap();
    let start = readme.find("```ron\n").unwrap() + "```ron\n".len();
    let text = &readme[start..start + readme[start..].find("```").unwrap()];
    let built = Case::from_str(text, "README.md")
        .unwrap()
        .build(None)
        .unwrap();
    assert_eq!(
        built.model.system().rods[0].route.as_ref().map(Vec::len),
        Some(3)
    );
}

#[test]
fn helix_case_matches_the_analytic_helix() {
    let built = Case::from_path(cases_dir().join("helix_fig4.ron"))
        .unwrap()
        .build(None)
        .unwrap();
    let spec = &built.model.system().rods[0];
    let (rho, alpha) = (0.2, std::f64::consts::FRAC_PI_8);
    let length = 2.0 * std::f64::consts::PI * rho / alpha.cos();
    assert!((spec.rod.length() - length).abs() < 1e-12);
    let end = spec.end.support.position().unwrap();
    assert!((end - Vector3::new(rho, 0.0, length * alpha.sin())).norm() < 1e-12);
    let frame = spec.start.support.frame().unwrap();
    assert!((frame * Vector3::z() - Vector3::new(0.0, alpha.cos(), alpha.sin())).norm() < 1e-12);
    assert!((frame * Vector3::x() - Vector3::new(-1.0, 0.0, 0.0)).norm() < 1e-12);
    assert_eq!(spec.route.as_ref().map(Vec::len), Some(24));
}
