//! The experiment files of a folder: which entries are experiments, in which order, and
//! reading one safely (a regular file of bounded size, never a FIFO or a device).

use std::fs;
use std::io::Read;
use std::path::{Path, PathBuf};

use super::ids::table_order;
use crate::experiment::ExperimentError;

/// The `(stem, path)` of every directory entry whose name ends in `.toml`, in table order.
///
/// Entries are not opened or followed here: what they are is for [`read_experiment_file`] to
/// find out, so that an odd entry is named rather than skipped. So is a name that ends in
/// another case of `.toml` (`IV.1.TOML`), which [`read_experiment_file`] refuses naming the
/// file, unless a `.toml` file of the same stem is there (that one is the experiment).
pub(in crate::experiment) fn experiment_entries(
    dir: &Path,
) -> Result<Vec<(String, PathBuf)>, ExperimentError> {
    let read_dir_error = |source| ExperimentError::ReadDir {
        dir: dir.to_path_buf(),
        source,
    };
    let mut files: Vec<(String, PathBuf)> = Vec::new();
    let mut other_case: Vec<(String, PathBuf)> = Vec::new();
    for entry in fs::read_dir(dir).map_err(read_dir_error)? {
        let path = entry.map_err(read_dir_error)?.path();
        let Some(extension) = path.extension().and_then(|e| e.to_str()) else {
            continue;
        };
        if !extension.eq_ignore_ascii_case("toml") {
            continue;
        }
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        if extension == "toml" {
            files.push((stem, path));
        } else {
            other_case.push((stem, path));
        }
    }
    for (stem, path) in other_case {
        if !files.iter().any(|(s, _)| *s == stem) {
            files.push((stem, path));
        }
    }
    files.sort_by_key(|(stem, _)| table_order(stem));
    Ok(files)
}

/// Largest experiment file read, in bytes. The largest shipped file has a few kilobytes; the
/// cap keeps a mistaken path (a log, a disk image) from being read into memory.
pub const MAX_FILE_BYTES: u64 = 16 * 1024 * 1024;

/// The text of an experiment file: a regular file (a symbolic link to one is fine) named
/// `*.toml` of at most [`MAX_FILE_BYTES`], in UTF-8 (an invalid byte is named with its line and
/// column).
///
/// What the path is gets checked before it is opened, since opening a FIFO blocks until a writer
/// comes and a device like `/dev/zero` has no end. The size is checked from the metadata and
/// again while reading (through `take`), in case the file grows in between.
pub(in crate::experiment) fn read_experiment_file(path: &Path) -> Result<String, ExperimentError> {
    let read_error = |source| ExperimentError::Read {
        path: path.to_path_buf(),
        source,
    };
    if let Some(extension) = path
        .extension()
        .and_then(|e| e.to_str())
        .filter(|e| *e != "toml")
    {
        return Err(read_error(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!(
                "the name ends in `.{extension}`, not `.toml`; rename it to `{}.toml`",
                path.file_stem().unwrap_or_default().to_string_lossy()
            ),
        )));
    }
    let metadata = fs::metadata(path).map_err(read_error)?;
    if !metadata.is_file() {
        return Err(ExperimentError::NotRegularFile {
            path: path.to_path_buf(),
            kind: file_kind(&metadata.file_type()),
        });
    }
    let too_large = |size| ExperimentError::TooLarge {
        path: path.to_path_buf(),
        size,
        limit: MAX_FILE_BYTES,
    };
    if metadata.len() > MAX_FILE_BYTES {
        return Err(too_large(metadata.len()));
    }
    let file = fs::File::open(path).map_err(read_error)?;
    let mut bytes = Vec::new();
    file.take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(read_error)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(too_large(bytes.len() as u64));
    }
    String::from_utf8(bytes).map_err(|e| read_error(not_utf8(e.as_bytes(), e.utf8_error())))
}

/// The error of a file that is not UTF-8: where the first invalid byte is (line and column, the
/// column counted in characters) and what it is, e.g. a Latin-1 `é` (0xE9).
fn not_utf8(bytes: &[u8], error: std::str::Utf8Error) -> std::io::Error {
    let at = error.valid_up_to();
    // Valid UTF-8 up to `at`, by the error's definition.
    let before = std::str::from_utf8(&bytes[..at]).unwrap_or_default();
    let line = 1 + before.matches('\n').count();
    let column = 1 + before
        .rsplit('\n')
        .next()
        .unwrap_or_default()
        .chars()
        .count();
    std::io::Error::new(
        std::io::ErrorKind::InvalidData,
        format!(
            "not UTF-8: line {line}, column {column}: byte 0x{:02X} (experiment files are \
             UTF-8; a file saved as Latin-1 or Windows-1252 needs converting, e.g. with \
             `iconv -f latin1 -t utf-8`)",
            bytes[at]
        ),
    )
}

/// What a path that is not a regular file is, for the error message.
pub(super) fn file_kind(file_type: &fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if file_type.is_fifo() {
            return "a FIFO";
        }
        if file_type.is_char_device() {
            return "a character device";
        }
        if file_type.is_block_device() {
            return "a block device";
        }
        if file_type.is_socket() {
            return "a socket";
        }
    }
    if file_type.is_dir() {
        "a directory"
    } else {
        "neither a file nor a directory"
    }
}
