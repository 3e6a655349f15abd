//! Where a machine project's files come from: the disk, or memory (tests and tools give their
//! programs, machine file and scenario as text, with no folder to make).

use indexmap::IndexMap;
use std::path::{Component, Path, PathBuf};

/// A place to read a project's files from.
pub trait Files {
    /// The text of the file at `path`.
    fn read(&self, path: &Path) -> std::io::Result<String>;
    /// The file's bytes, whatever their encoding (programs from old editors are not UTF-8).
    fn read_bytes(&self, path: &Path) -> std::io::Result<Vec<u8>> {
        self.read(path).map(String::into_bytes)
    }
    /// True when `path` is a folder.
    fn is_dir(&self, path: &Path) -> bool;
    /// True when a file or folder exists at `path`.
    fn exists(&self, path: &Path) -> bool;
    /// The entries of the folder `dir`.
    fn list(&self, dir: &Path) -> std::io::Result<Vec<PathBuf>>;
    /// The folder's own name (the machine's name when its file gives none).
    fn folder_name(&self, dir: &Path) -> Option<String>;
}

/// The disk.
#[derive(Debug, Clone, Copy, Default)]
pub struct Disk;

impl Files for Disk {
    fn read(&self, path: &Path) -> std::io::Result<String> {
        std::fs::read_to_string(path)
    }

    fn read_bytes(&self, path: &Path) -> std::io::Result<Vec<u8>> {
        std::fs::read(path)
    }

    fn is_dir(&self, path: &Path) -> bool {
        path.is_dir()
    }

    fn exists(&self, path: &Path) -> bool {
        path.exists()
    }

    fn list(&self, dir: &Path) -> std::io::Result<Vec<PathBuf>> {
        Ok(std::fs::read_dir(dir)?
            .filter_map(Result::ok)
            .map(|e| e.path())
            .collect())
    }

    fn folder_name(&self, dir: &Path) -> Option<String> {
        let full = dir.canonicalize().ok()?;
        full.file_name().map(|n| n.to_string_lossy().into_owned())
    }
}

/// Files held in memory, by path; the folders are those their paths name.
#[derive(Debug, Clone, Default)]
pub struct Memory {
    files: IndexMap<PathBuf, String>,
}

impl Memory {
    /// No files yet.
    pub fn new() -> Memory {
        Memory::default()
    }

    /// Add (or replace) the file at `path` with `text`.
    pub fn file(mut self, path: impl AsRef<Path>, text: impl Into<String>) -> Memory {
        self.files.insert(normal(path.as_ref()), text.into());
        self
    }
}

/// `path` without `.` components or a trailing separator, so `m/./a.pt` and `m/a.pt` are one
/// file.
fn normal(path: &Path) -> PathBuf {
    path.components()
        .filter(|c| !matches!(c, Component::CurDir))
        .collect()
}

impl Files for Memory {
    fn read(&self, path: &Path) -> std::io::Result<String> {
        self.files.get(&normal(path)).cloned().ok_or_else(|| {
            std::io::Error::new(std::io::ErrorKind::NotFound, "no such file in memory")
        })
    }

    fn is_dir(&self, path: &Path) -> bool {
        let dir = normal(path);
        self.files.keys().any(|f| f.starts_with(&dir) && f != &dir)
    }

    fn exists(&self, path: &Path) -> bool {
        self.files.contains_key(&normal(path)) || self.is_dir(path)
    }

    fn list(&self, dir: &Path) -> std::io::Result<Vec<PathBuf>> {
        let dir = normal(dir);
        let mut out: Vec<PathBuf> = Vec::new();
        for f in self.files.keys() {
            let Ok(rest) = f.strip_prefix(&dir) else {
                continue;
            };
            if let Some(first) = rest.components().next() {
                let entry = dir.join(first);
                if !out.contains(&entry) {
                    out.push(entry);
                }
            }
        }
        if out.is_empty() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::NotFound,
                "no such folder in memory",
            ));
        }
        Ok(out)
    }

    fn folder_name(&self, dir: &Path) -> Option<String> {
        normal(dir)
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn memory_files_have_folders() {
        let m = Memory::new()
            .file("cell/machine.toml", "[machine]")
            .file("./cell/p1.pt", "End");
        assert!(m.is_dir(Path::new("cell")));
        assert!(!m.is_dir(Path::new("cell/p1.pt")));
        assert!(m.exists(Path::new("cell/p1.pt")));
        assert_eq!(m.read(Path::new("cell/./p1.pt")).expect("read"), "End");
        let mut listed = m.list(Path::new("cell")).expect("a folder");
        listed.sort();
        assert_eq!(
            listed,
            vec![
                PathBuf::from("cell/machine.toml"),
                PathBuf::from("cell/p1.pt")
            ]
        );
        assert_eq!(m.folder_name(Path::new("cell")).as_deref(), Some("cell"));
        assert!(m.read(Path::new("cell/none.pt")).is_err());
    }
}
