//! How geardyn writes files: through a temporary file renamed into place (a reader never sees a
//! half-written file, a killed run leaves none), never through a symbolic link or into a
//! non-regular file, and with errors that name the path. The lowest layer of everything that
//! writes: data tables and run records (`geardyn-io`), figures (`geardyn-plots`).
#![warn(missing_docs)]

pub mod safe_write;
pub use safe_write::OutputError;
