//! Independent reference solutions used by the validation tests.
//!
//! Everything in this library is self-contained (pure `f64` Rust, only
//! `nalgebra` for small matrices) and does **not** depend on any other crate
//! of the workspace, so that the discrete rod solver can be validated
//! against it.  Units are SI throughout: lengths in m, forces in N,
//! moments in N·m, stiffnesses in N (axial/shear) and N·m² (bending /
//! torsion), angles in rad.
//!
//! * [`reference::reissner_planar`] — planar Reissner elastica (extensible,
//!   shearable) under a tip dead load or with a prescribed tip position,
//!   solved by shooting with a 16th-order extrapolation integrator
//!   (tip-position error < 1e-12 m).
//! * [`reference::euler_bernoulli`] — closed-form linear beam results:
//!   cantilever (with optional Timoshenko shear correction) and propped
//!   cantilevers.
//! * [`reference::kirchhoff_helix`] — exact helical equilibria of an
//!   isotropic Kirchhoff rod (Love, Art. 270), with optional extra twist.
//! * [`reference::catenary`] — the elastic catenary (Irvine's closed form,
//!   `H` and `V` by Newton).
//! * [`reference::heavy_cantilever`] — a planar Reissner cantilever under its
//!   own weight (shooting on the clamp moment).
//! * [`reference::buckling`] — clamped–clamped post-buckling (elliptic
//!   integrals, and shooting for an extensible, shearable rod) and Greenhill's
//!   twist-buckling threshold of a clamped rod.
//! * [`reference::ode`] — the fixed-step Gragg–Bulirsch–Stoer integrator
//!   shared by the references.
//!
//! The parameter grid of the solver's convergence map lives in `strand_cli::bench::grid`
//! (shared with `strand bench --grid`).
pub mod reference;
