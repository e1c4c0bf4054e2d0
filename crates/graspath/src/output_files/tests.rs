//! The output rules checked against the file system itself: what exists afterwards, byte for
//! byte, and that nothing else (no temporary file or folder) does.

use super::*;

/// Every entry under `dir`, relative, sorted (folders end in `/`).
fn tree(dir: &Path) -> Vec<String> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<String>) {
        for entry in std::fs::read_dir(dir).expect("list") {
            let entry = entry.expect("entry");
            let path = entry.path();
            let relative = path
                .strip_prefix(root)
                .expect("inside")
                .display()
                .to_string();
            let file_type = std::fs::symlink_metadata(&path).expect("stat").file_type();
            if file_type.is_dir() {
                out.push(format!("{relative}/"));
                walk(root, &path, out);
            } else {
                out.push(relative);
            }
        }
    }
    let mut out = Vec::new();
    walk(dir, dir, &mut out);
    out.sort();
    out
}

fn set(names: &[(&str, &str)]) -> Vec<(String, Vec<u8>)> {
    names
        .iter()
        .map(|(n, b)| (n.to_string(), b.as_bytes().to_vec()))
        .collect()
}

#[test]
fn a_new_file_is_written_whole_and_alone() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("out.json");
    write_file(&path, b"{}", Existing::Refuse).expect("write");
    assert_eq!(std::fs::read(&path).expect("read"), b"{}");
    assert_eq!(tree(dir.path()), ["out.json"]);
}

#[test]
fn an_existing_file_is_replaced_only_when_allowed() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("out.json");
    std::fs::write(&path, "old").expect("seed");
    let err = write_file(&path, b"new", Existing::Refuse).expect_err("refused");
    assert!(matches!(err.kind, OutputErrorKind::FileExists));
    assert!(err.is_refusal());
    assert!(
        err.to_string().contains("replacing it was not allowed"),
        "{err}"
    );
    assert!(
        !err.to_string().contains("--"),
        "no command-line flag: {err}"
    );
    assert!(err.to_string().starts_with(&path.display().to_string()));
    assert_eq!(std::fs::read(&path).expect("read"), b"old");
    write_file(&path, b"new", Existing::Replace).expect("replace");
    assert_eq!(std::fs::read(&path).expect("read"), b"new");
    assert_eq!(tree(dir.path()), ["out.json"]);
}

#[cfg(unix)]
#[test]
fn links_devices_and_fifos_are_never_written_through_or_replaced() {
    let dir = tempfile::tempdir().expect("tempdir");
    let target = dir.path().join("real.json");
    std::fs::write(&target, "keep").expect("seed");
    let link = dir.path().join("link.json");
    std::os::unix::fs::symlink(&target, &link).expect("symlink");
    let dangling = dir.path().join("dangling");
    std::os::unix::fs::symlink(dir.path().join("nowhere"), &dangling).expect("symlink");
    for existing in [Existing::Refuse, Existing::Replace] {
        for path in [&link, &dangling] {
            let err = write_file(path, b"x", existing).expect_err("a link");
            assert!(matches!(err.kind, OutputErrorKind::Symlink(_)), "{err}");
            let err = write_files(path, &set(&[("a", "x")]), existing).expect_err("a link");
            assert!(matches!(err.kind, OutputErrorKind::Symlink(_)), "{err}");
        }
        let err = write_file(Path::new("/dev/null"), b"x", existing).expect_err("a device");
        assert!(err.to_string().contains("character device"), "{err}");
    }
    assert_eq!(std::fs::read(&target).expect("read"), b"keep");
    assert!(std::fs::symlink_metadata(&link)
        .expect("stat")
        .file_type()
        .is_symlink());
    assert_eq!(tree(dir.path()), ["dangling", "link.json", "real.json"]);
    let fifo = dir.path().join("fifo");
    if std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success())
    {
        let err = write_file(&fifo, b"x", Existing::Replace).expect_err("a fifo");
        assert!(err.to_string().contains("FIFO"), "{err}");
    }
}

#[test]
fn files_and_folders_are_not_taken_for_each_other() {
    let dir = tempfile::tempdir().expect("tempdir");
    let file = dir.path().join("f");
    std::fs::write(&file, "x").expect("seed");
    let err = write_files(&file, &set(&[("a", "1")]), Existing::Replace).expect_err("a file");
    assert!(matches!(
        err.kind,
        OutputErrorKind::WrongKind {
            found: "file",
            wanted: "folder"
        }
    ));
    let err = write_file(dir.path(), b"x", Existing::Replace).expect_err("a folder");
    assert!(matches!(
        err.kind,
        OutputErrorKind::WrongKind {
            found: "folder",
            ..
        }
    ));
    let err = write_file(&file.join("below"), b"x", Existing::Replace).expect_err("under a file");
    assert!(
        matches!(err.kind, OutputErrorKind::ParentNotFolder),
        "{err}"
    );
    assert_eq!(tree(dir.path()), ["f"]);
}

#[test]
fn a_set_appears_in_a_new_folder_with_its_subfolders_and_missing_parents() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("a/b/out");
    let written = write_files(
        &out,
        &set(&[("x.json", "1"), ("sub/y.json", "2"), ("sub/deeper/z", "3")]),
        Existing::Refuse,
    )
    .expect("write");
    assert_eq!(
        written,
        [
            out.join("x.json"),
            out.join("sub/y.json"),
            out.join("sub/deeper/z")
        ]
    );
    assert_eq!(
        tree(dir.path()),
        [
            "a/",
            "a/b/",
            "a/b/out/",
            "a/b/out/sub/",
            "a/b/out/sub/deeper/",
            "a/b/out/sub/deeper/z",
            "a/b/out/sub/y.json",
            "a/b/out/x.json"
        ]
    );
    assert_eq!(std::fs::read(out.join("sub/y.json")).expect("read"), b"2");
}

#[test]
fn an_empty_folder_is_filled_and_a_full_one_replaced_only_when_allowed() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("out");
    std::fs::create_dir(&out).expect("seed");
    write_files(
        &out,
        &set(&[("candidates.json", "1"), ("pairs.json", "p")]),
        Existing::Refuse,
    )
    .expect("empty folder");
    let err = write_files(&out, &set(&[("candidates.json", "2")]), Existing::Refuse)
        .expect_err("not empty");
    assert!(matches!(err.kind, OutputErrorKind::FolderNotEmpty(_)));
    assert!(
        err.to_string().contains("replacing it was not allowed"),
        "{err}"
    );
    assert_eq!(
        std::fs::read(out.join("candidates.json")).expect("read"),
        b"1"
    );
    // Replacing drops the earlier run's pairs.json: nothing stale mixes with the new set.
    write_files(&out, &set(&[("candidates.json", "2")]), Existing::Replace).expect("replace");
    assert_eq!(tree(dir.path()), ["out/", "out/candidates.json"]);
    assert_eq!(
        std::fs::read(out.join("candidates.json")).expect("read"),
        b"2"
    );
}

#[test]
fn a_failed_set_leaves_nothing_behind() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("new/parent/out");
    // "a" is a file, so "a/b" cannot be written: the failure comes after the first file.
    let err = write_files(&out, &set(&[("a", "1"), ("a/b", "2")]), Existing::Refuse)
        .expect_err("collision");
    assert!(!err.is_refusal());
    assert!(err.to_string().contains("'a/b'"), "{err}");
    assert!(tree(dir.path()).is_empty(), "{:?}", tree(dir.path()));
    // The same failure over an existing folder keeps the old contents.
    let old = dir.path().join("old");
    write_files(&old, &set(&[("keep", "k")]), Existing::Refuse).expect("seed");
    write_files(&old, &set(&[("a", "1"), ("a/b", "2")]), Existing::Replace).expect_err("collision");
    assert_eq!(tree(dir.path()), ["old/", "old/keep"]);
    for bad in ["", "/abs", "../up", "a/../b", "."] {
        let err = write_files(&out, &set(&[(bad, "x")]), Existing::Refuse).expect_err(bad);
        assert!(
            matches!(err.kind, OutputErrorKind::BadName(_)),
            "{bad}: {err}"
        );
    }
    let err =
        write_files(&out, &set(&[("x", "1"), ("x", "2")]), Existing::Refuse).expect_err("twice");
    assert!(matches!(err.kind, OutputErrorKind::DuplicateName(_)));
    assert_eq!(tree(dir.path()), ["old/", "old/keep"]);
}

#[test]
fn a_failed_swap_puts_the_old_folder_back() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("out");
    write_files(&out, &set(&[("keep", "k")]), Existing::Refuse).expect("seed");
    // The new folder does not exist, so renaming it in fails after the old one moved aside.
    let err = folder::replace_folder(&dir.path().join("missing"), &out).expect_err("no new folder");
    assert!(matches!(err.kind, OutputErrorKind::Io { .. }), "{err}");
    assert_eq!(tree(dir.path()), ["out/", "out/keep"]);
}

#[test]
fn the_working_folder_and_its_ancestors_are_never_replaced() {
    let cwd = std::env::current_dir().expect("cwd");
    assert_eq!(protected(&cwd), Some("the working folder"));
    assert_eq!(
        protected(cwd.parent().expect("parent")),
        Some("an ancestor of the working folder")
    );
    assert_eq!(protected(Path::new("/")), Some("the root folder"));
    let dir = tempfile::tempdir().expect("tempdir");
    assert_eq!(protected(dir.path()), None);
}

#[test]
fn a_failed_write_keeps_the_operating_system_error_as_its_source() {
    let dir = tempfile::tempdir().expect("tempdir");
    let err = write_file(&dir.path().join("no/such\0name"), b"x", Existing::Replace)
        .expect_err("a name with a NUL byte");
    assert!(matches!(err.kind, OutputErrorKind::Io { .. }), "{err}");
    let source = std::error::Error::source(&err).expect("the io error");
    assert!(source.downcast_ref::<std::io::Error>().is_some());
    assert!(
        !err.to_string().contains(&source.to_string()),
        "said once: {err}"
    );
    assert_eq!(tree(dir.path()), Vec::<String>::new());
}
