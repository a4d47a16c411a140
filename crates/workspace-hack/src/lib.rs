//! No code. This crate only pins the features of dependencies shared by every build of the
//! geardyn crates (see its `Cargo.toml`), so that the workspace's tests, the command-line
//! program and the Python extension compile them once, identically.
