//! The rules every tool applies to the files a user names: an input is a regular file (after following
//! symlinks) no larger than a stated cap, so `/dev/zero`, a FIFO or a directory is a clear error instead of
//! a read that never ends; an output is never one of the inputs (the same file by device and inode, however
//! it is named: another path, a symlink or a hard link) nor a file of a bag being read.
//!
//! The bag readers apply the same regular-file rule to MCAP files ([`not_regular`]); their size is not capped
//! (they are read a chunk at a time).
//!
//! Every input opened through this module, the bag reader or `import`'s table reader is noted ([`note_input`]),
//! so [`refuse_clobber`] also refuses an output that is any file the process has read, named on the command line
//! or not (a bat file's profile CSV, a batter file, a column map).

use std::io::Read;
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

/// Largest text input a tool reads whole (case files, batter files, bat files and their profile CSV, QoS
/// override files, `--params-file`, `pub --file`), bytes: 16 MiB, far beyond any such file (a bat profile at
/// the most stations a BatParams may carry is ~200 kB).
pub const MAX_INPUT_BYTES: u64 = 16 << 20;

/// Why an input file was refused.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    /// The file could not be opened or read. The OS error is in the message and deliberately not a `source`
    /// too: an error chain printed whole would say it twice.
    #[error("cannot read {what} '{path}': {error}")]
    Io { what: String, path: PathBuf, error: std::io::Error },
    /// Not a regular file (after following symlinks).
    #[error("{what} '{path}' is {kind}, not a regular file: refused")]
    NotRegular { what: String, path: PathBuf, kind: &'static str },
    /// Larger than the cap.
    #[error("{what} '{path}' is {size} bytes, over the limit of {limit} bytes for an input file: refused")]
    TooLarge { what: String, path: PathBuf, size: u64, limit: u64 },
    /// Not UTF-8 text.
    #[error("{what} '{path}' is not UTF-8 text")]
    NotText { what: String, path: PathBuf },
}

/// What a file type is when it is not a regular file (`None` for a regular file).
pub fn not_regular(file_type: std::fs::FileType) -> Option<&'static str> {
    use std::os::unix::fs::FileTypeExt;
    if file_type.is_file() {
        None
    } else if file_type.is_dir() {
        Some("a directory")
    } else if file_type.is_fifo() {
        Some("a FIFO")
    } else if file_type.is_char_device() {
        Some("a character device")
    } else if file_type.is_block_device() {
        Some("a block device")
    } else if file_type.is_socket() {
        Some("a socket")
    } else {
        Some("not a regular file")
    }
}

/// Reads the whole of `path` (described as `what` in errors, e.g. "case file") if it is a regular file of at
/// most `limit` bytes. Never blocks on a FIFO (it is refused before it is opened, and opened non-blocking)
/// and never reads more than `limit + 1` bytes, whatever the file does meanwhile.
pub fn read_limited(path: &Path, what: &str, limit: u64) -> Result<Vec<u8>, InputError> {
    use std::os::unix::fs::OpenOptionsExt;
    let io = |error| InputError::Io { what: what.to_string(), path: path.to_path_buf(), error };
    let refuse = |kind| InputError::NotRegular { what: what.to_string(), path: path.to_path_buf(), kind };
    let too_large = |size| InputError::TooLarge { what: what.to_string(), path: path.to_path_buf(), size, limit };
    let meta = std::fs::metadata(path).map_err(io)?;
    if let Some(kind) = not_regular(meta.file_type()) {
        return Err(refuse(kind));
    }
    if meta.len() > limit {
        return Err(too_large(meta.len()));
    }
    let file = std::fs::OpenOptions::new().read(true).custom_flags(libc::O_NONBLOCK).open(path).map_err(io)?;
    let meta = file.metadata().map_err(io)?;
    if let Some(kind) = not_regular(meta.file_type()) {
        return Err(refuse(kind));
    }
    note_input(path, &meta);
    let mut bytes = Vec::with_capacity(meta.len().min(limit) as usize);
    file.take(limit + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(too_large(bytes.len() as u64));
    }
    Ok(bytes)
}

/// [`read_limited`] at [`MAX_INPUT_BYTES`], as UTF-8 text.
pub fn read_text(path: &Path, what: &str) -> Result<String, InputError> {
    let bytes = read_limited(path, what, MAX_INPUT_BYTES)?;
    String::from_utf8(bytes).map_err(|_| InputError::NotText { what: what.to_string(), path: path.to_path_buf() })
}

/// (device, inode) of the file at `path` after following symlinks; `None` when it does not exist.
fn identity(path: &Path) -> Option<(u64, u64)> {
    std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()))
}

/// The files this process has opened as inputs: (device, inode) and the path they were opened by.
static INPUTS_READ: std::sync::Mutex<Vec<((u64, u64), PathBuf)>> = std::sync::Mutex::new(Vec::new());

/// Notes that the file at `path`, whose metadata (of the opened file) is `meta`, is an input of this process:
/// [`refuse_clobber`] refuses it as an output from now on.
pub fn note_input(path: &Path, meta: &std::fs::Metadata) {
    let id = (meta.dev(), meta.ino());
    let mut read = INPUTS_READ.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    // An entry of the same identity whose path leads elsewhere now was a deleted file's: this one replaces it.
    read.retain(|(seen, noted)| *seen != id || identity(noted) == Some(id));
    if !read.iter().any(|(seen, _)| *seen == id) {
        read.push((id, path.to_path_buf()));
    }
}

/// The input noted by [`note_input`] that is the file `id`, if any. Its path must still lead to that file: an
/// input since deleted can have its inode reused by a new file, which was never read.
fn noted_input(id: (u64, u64)) -> Option<PathBuf> {
    let read = INPUTS_READ.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    read.iter().find(|(seen, path)| *seen == id && identity(path) == Some(id)).map(|(_, path)| path.clone())
}

/// The files a bag at `path` is made of: the path itself when it is a file, else every file directly in the
/// directory (its MCAP files and `metadata.yaml`, and anything else lying there).
pub fn bag_files(path: &Path) -> Vec<PathBuf> {
    match std::fs::read_dir(path) {
        Ok(entries) => entries.filter_map(|e| e.ok().map(|e| e.path())).filter(|p| p.is_file()).collect(),
        Err(_) => vec![path.to_path_buf()],
    }
}

/// Refuses `output` (named by `flag`) when it is — under any name, through a symlink or a hard link — one of
/// `inputs`, a file of a bag among `bags`, or any other file this process has read ([`note_input`]); or a new
/// file inside a bag directory among `bags` (which would become part of that bag). An output that does not
/// exist yet cannot be an input file; its directory is compared canonicalised. The one rule of every command
/// that writes (docs/cli.md, "Files a command writes").
pub fn refuse_clobber(flag: &str, output: &Path, inputs: &[PathBuf], bags: &[PathBuf]) -> Result<(), String> {
    let mut files: Vec<PathBuf> = inputs.to_vec();
    for bag in bags {
        files.extend(bag_files(bag));
    }
    if let Some(out) = identity(output) {
        let input = files.into_iter().find(|f| identity(f) == Some(out)).or_else(|| noted_input(out));
        if let Some(input) = input {
            return Err(format!(
                "{flag} '{}' is the input file '{}': refused (it would be overwritten while it is read)",
                output.display(),
                input.display()
            ));
        }
    }
    let parent = match output.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if let Ok(dir) = parent.canonicalize() {
        for bag in bags {
            if bag.is_dir() && bag.canonicalize().is_ok_and(|b| b == dir) {
                return Err(format!(
                    "{flag} '{}' is inside the bag directory '{}' being read: refused (write it elsewhere)",
                    output.display(),
                    bag.display()
                ));
            }
        }
    }
    Ok(())
}

/// Most bytes of a user's input an error or report quotes ([`echo`]): a name, a cell or a number is read
/// at a glance within it, and a 1-MB cell or a 300-digit number cannot flood the terminal.
pub const ECHO_BYTES: usize = 80;

/// `text` as an error or report quotes a user's input: at most [`ECHO_BYTES`] bytes (cut on a character
/// boundary), with `…` and the input's full length when cut.
pub fn echo(text: &str) -> std::borrow::Cow<'_, str> {
    crate::limits::shorten(text, ECHO_BYTES)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_regular_files_within_the_cap_are_read() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("case.toml");
        std::fs::write(&file, "a = 1\n").unwrap();
        assert_eq!(read_text(&file, "case file").unwrap(), "a = 1\n");
        let e = read_limited(&file, "case file", 3).unwrap_err().to_string();
        assert!(e.contains("6 bytes, over the limit of 3 bytes"), "{e}");
        let e = read_text(dir.path(), "case file").unwrap_err().to_string();
        assert!(e.contains("is a directory, not a regular file"), "{e}");
        let e = read_text(Path::new("/dev/zero"), "batter file").unwrap_err().to_string();
        assert!(e.contains("'/dev/zero' is a character device"), "{e}");
        let fifo = dir.path().join("fifo");
        let name = std::ffi::CString::new(fifo.as_os_str().as_encoded_bytes()).unwrap();
        assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0);
        let e = read_text(&fifo, "QoS override file").unwrap_err().to_string();
        assert!(e.contains("is a FIFO"), "{e}");
        let e = read_text(&dir.path().join("missing"), "bat file").unwrap_err().to_string();
        assert!(e.starts_with("cannot read bat file"), "{e}");
    }

    #[test]
    fn an_output_is_never_an_input_by_any_name() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("in.toml");
        std::fs::write(&input, "x").unwrap();
        let inputs = vec![input.clone()];
        assert!(refuse_clobber("-o", &input, &inputs, &[]).is_err());
        let link = dir.path().join("link.toml");
        std::os::unix::fs::symlink(&input, &link).unwrap();
        assert!(refuse_clobber("-o", &link, &inputs, &[]).is_err(), "symlink");
        let hard = dir.path().join("hard.toml");
        std::fs::hard_link(&input, &hard).unwrap();
        assert!(refuse_clobber("-o", &hard, &inputs, &[]).is_err(), "hard link");
        let dotted = dir.path().join(".").join("in.toml");
        assert!(refuse_clobber("-o", &dotted, &inputs, &[]).is_err(), "another spelling");
        assert!(refuse_clobber("-o", &dir.path().join("new.toml"), &inputs, &[]).is_ok());
        // A bag: every file in its directory, and new files in it.
        let bag = dir.path().join("bag");
        std::fs::create_dir(&bag).unwrap();
        std::fs::write(bag.join("bag_0.mcap"), "m").unwrap();
        std::fs::write(bag.join("metadata.yaml"), "y").unwrap();
        let bags = vec![bag.clone()];
        let e = refuse_clobber("--write", &bag.join("bag_0.mcap"), &[], &bags).unwrap_err();
        assert!(e.contains("is the input file"), "{e}");
        assert!(refuse_clobber("--write", &bag.join("metadata.yaml"), &[], &bags).is_err());
        let e = refuse_clobber("--write", &bag.join("fitted.jsonl"), &[], &bags).unwrap_err();
        assert!(e.contains("inside the bag directory"), "{e}");
        assert!(refuse_clobber("--write", &dir.path().join("fitted.jsonl"), &[], &bags).is_ok());
    }

    #[test]
    fn an_output_is_never_a_file_the_process_has_read() {
        let dir = tempfile::tempdir().unwrap();
        let profile = dir.path().join("profile.csv");
        std::fs::write(&profile, "z_m,outer_radius_m\n").unwrap();
        let link = dir.path().join("figure.svg");
        std::os::unix::fs::symlink(&profile, &link).unwrap();
        // Not read yet, not named as an input: nothing says it is one.
        assert!(refuse_clobber("--plot", &link, &[], &[]).is_ok());
        read_text(&profile, "bat profile").unwrap();
        let e = refuse_clobber("--plot", &link, &[], &[]).unwrap_err();
        assert!(e.contains("is the input file") && e.contains("profile.csv"), "{e}");
        // A file the process never read stays writable.
        assert!(refuse_clobber("--plot", &dir.path().join("other.svg"), &[], &[]).is_ok());
    }

    #[test]
    fn a_deleted_input_s_inode_reused_by_a_new_file_is_not_an_input() {
        let dir = tempfile::tempdir().unwrap();
        let read = dir.path().join("read.csv");
        std::fs::write(&read, "x\n").unwrap();
        read_text(&read, "input").unwrap();
        std::fs::remove_file(&read).unwrap();
        // Whatever inode the filesystem hands out next (often the one just freed), a new file was never read.
        let fresh = dir.path().join("fresh.svg");
        std::fs::write(&fresh, "").unwrap();
        assert!(refuse_clobber("--plot", &fresh, &[], &[]).is_ok());
        // Read now, it is an input, whatever was noted under its inode before.
        read_text(&fresh, "input").unwrap();
        assert!(refuse_clobber("--plot", &fresh, &[], &[]).is_err());
    }

    #[test]
    fn an_echoed_input_is_cut_past_its_bound_and_says_how_long_it_was() {
        let exact = "9".repeat(ECHO_BYTES);
        assert_eq!(echo(&exact), exact, "{ECHO_BYTES} bytes are quoted whole");
        let over = "9".repeat(ECHO_BYTES + 1);
        assert_eq!(echo(&over), format!("{}…({} bytes)", "9".repeat(ECHO_BYTES), ECHO_BYTES + 1));
        // A 300-digit number, as 1e308 written out, comes back as its first 80 digits.
        let digits = format!("{:.0}", 1e308);
        assert_eq!(digits.len(), 309);
        assert!(echo(&digits).len() < 100);
        // Never inside a character: 79 ASCII bytes and a 2-byte é at the bound.
        let accented = format!("{}é{}", "a".repeat(ECHO_BYTES - 1), "b".repeat(10));
        assert!(echo(&accented).starts_with(&format!("{}…", "a".repeat(ECHO_BYTES - 1))));
    }
}
