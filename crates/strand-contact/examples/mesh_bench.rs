//! BVH build and query timings on generated wavy surfaces (1M and 4M triangles by
//! default). Run in release mode:
//!
//! `cargo run --release -p strand-contact --example mesh_bench [triangles...]`

fn main() {
    let sizes: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let sizes = if sizes.is_empty() {
        vec![1_000_000, 4_000_000]
    } else {
        sizes
    };
    for triangles in sizes {
        match strand_contact::bench::time_wavy_surface(triangles, 20_000) {
            Ok(t) => println!(
                "{:>9} triangles: mesh build {:7.1} ms (parry TriMesh+BVH alone {:7.1} ms), {} queries ({} hits) {:6.2} µs/query",
                t.triangles,
                t.build_seconds * 1e3,
                t.bvh_seconds * 1e3,
                t.queries,
                t.hits,
                t.seconds_per_query * 1e6
            ),
            Err(e) => eprintln!("error: {e}"),
        }
    }
}
