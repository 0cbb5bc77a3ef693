//! Workspace-level validation of Strand against independent references: the planar
//! Reissner elastica (shooting, `strand_tests::reference`), Kirchhoff's helix,
//! Euler–Bernoulli beams, conservation laws (the paper's first integrals) and global
//! equilibrium. One test binary; each module is one topic.

mod balance;
mod batch;
mod buckling;
mod cad;
mod cantilever;
mod catenary;
mod cli;
mod clips;
mod common;
mod contact;
mod convergence_map;
mod cooler;
mod drop;
mod elastica;
mod end_forces;
mod groove;
mod guess;
mod harness;
mod heavy_cantilever;
mod helix;
mod junction;
mod motion;
mod moulded_clips;
mod optimize;
mod predeformed;
mod proximity;
mod report;
mod sensitivity;
mod sensitivity_exact;
mod sensitivity_local;
mod start_checks;
mod study;
mod translation;
mod twist;
