//! Frame-graph compile tests.
