//! Workspace-level validation of Strand against independent references: the planar
//! Reissner elastica (shooting, `strand_tests::reference`), Kirchhoff's helix,
//! Euler–Bernoulli beams, conservation laws (the paper's first integrals) and global
//! equilibrium. One test binary; each module is one topic.

mod balance;
mod batch;
mod cantilever;
mod cli;
mod clips;
mod common;
mod contact;
mod cooler;
mod elastica;
mod harness;
mod helix;
mod junction;
mod predeformed;
mod report;
mod study;
