//! Why a job did not run to its end: [`ExecError`], shared by the executor and the stores.

use geardyn_io::output::OutputError;
use geardyn_io::run_record::FolderError;

/// Why a job did not run to its end.
#[derive(Debug, thiserror::Error)]
pub enum ExecError {
    /// The output folder cannot take this run (another command's, another run's, in use).
    #[error(transparent)]
    Folder(#[from] FolderError),
    /// The store cannot be read or written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// The store refused (a shard store of another plan, damaged data, ...).
    #[error("{0}")]
    Store(String),
    /// The analysis itself refused or failed (its own error, unchanged).
    #[error(transparent)]
    Analysis(Box<dyn std::error::Error + Send + Sync>),
}

impl ExecError {
    /// The analysis' own error.
    pub fn analysis(e: impl std::error::Error + Send + Sync + 'static) -> Self {
        ExecError::Analysis(Box::new(e))
    }
}
