//! Where a bench writes what it makes (`bench scenes`, `bench scale`): the folder `--keep`
//! names, or a temporary one.

use anyhow::{Context as _, Result};

/// Where a bench writes its scenes, exports and images: the folder `--keep` names (made when
/// missing, left afterwards), else a temporary one removed when this is dropped.
pub(crate) enum WorkFolder {
    Kept(std::path::PathBuf),
    Temporary(tempfile::TempDir),
}

impl WorkFolder {
    pub(crate) fn new(keep: Option<&std::path::Path>) -> Result<WorkFolder> {
        Ok(match keep {
            Some(d) => {
                std::fs::create_dir_all(d).with_context(|| format!("making {}", d.display()))?;
                WorkFolder::Kept(d.to_path_buf())
            }
            None => WorkFolder::Temporary(tempfile::tempdir()?),
        })
    }

    pub(crate) fn path(&self) -> &std::path::Path {
        match self {
            WorkFolder::Kept(d) => d,
            WorkFolder::Temporary(t) => t.path(),
        }
    }
}
