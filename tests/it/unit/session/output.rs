//! Unit tests of `session::output` (`src/session/output.rs`).

use isola::session::output::*;
use std::path::Path;

#[test]
fn regular_files_replaced_streams_written_through_others_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let file = d.join("a.csv");
    write_output(&file, b"one", &Protected::none()).unwrap();
    write_output(&file, b"two", &Protected::none()).unwrap();
    assert_eq!(std::fs::read(&file).unwrap(), b"two");
    // through a link, the linked file is replaced and the link kept
    let link = d.join("link.csv");
    std::os::unix::fs::symlink(&file, &link).unwrap();
    write_output(&link, b"three", &Protected::none()).unwrap();
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert_eq!(std::fs::read(&file).unwrap(), b"three");
    // a character device is written through, never replaced
    let null = Path::new("/dev/null");
    write_output(null, b"gone", &Protected::none()).unwrap();
    use std::os::unix::fs::FileTypeExt;
    assert!(
        std::fs::metadata(null)
            .unwrap()
            .file_type()
            .is_char_device()
    );
    assert!(matches!(
        check_target(d, &Protected::none()),
        Err(OutputError::Directory { .. })
    ));
    assert!(matches!(
        check_target(&d.join("no/such/x.csv"), &Protected::none()),
        Err(OutputError::NoFolder { .. })
    ));
    let dangling = d.join("dangling.csv");
    std::os::unix::fs::symlink(d.join("nowhere"), &dangling).unwrap();
    assert!(matches!(
        check_target(&dangling, &Protected::none()),
        Err(OutputError::Special { .. })
    ));
}

#[test]
fn session_and_results_are_protected() {
    let dir = tempfile::tempdir().unwrap();
    let session = dir.path().join("s.toml");
    let results = dir.path().join("s.results");
    std::fs::write(&session, "schema = 1\n").unwrap();
    std::fs::create_dir(&results).unwrap();
    std::fs::write(results.join("b.csv"), "x").unwrap();
    let p = Protected::session(&session, &results);
    for target in [
        session.clone(),
        results.join("b.csv"),
        results.join("new.csv"),
        dir.path().join("./s.results/../s.toml"),
    ] {
        let e = check_target(&target, &p).unwrap_err();
        assert!(
            matches!(e, OutputError::Protected { .. }),
            "{target:?}: {e}"
        );
    }
    assert!(check_target(&dir.path().join("out.csv"), &p).is_ok());
    assert_eq!(std::fs::read_to_string(&session).unwrap(), "schema = 1\n");
}

/// A session's results folder is named after its whole file name but `.toml`: an editor's
/// backup, a copy or a file without the extension never shares the session's results.
#[test]
fn every_session_file_has_a_results_folder_of_its_own() {
    use isola::session::schema::results_dir_of;
    for (file, results) in [
        ("/d/s.toml", "/d/s.results"),
        ("/d/s.toml~", "/d/s.toml~.results"),
        ("/d/s.bak", "/d/s.bak.results"),
        ("/d/s.TOML", "/d/s.TOML.results"),
        ("/d/s", "/d/s.results"),
        ("/d/fig.06a.toml", "/d/fig.06a.results"),
    ] {
        assert_eq!(
            results_dir_of(Path::new(file)),
            Path::new(results),
            "{file}"
        );
    }
}
