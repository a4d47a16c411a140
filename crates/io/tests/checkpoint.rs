//! Crash-safe checkpoints (issue 13): torn and damaged lines cost only themselves, records can be
//! validated, and a rewrite replaces the file by a rename instead of truncating it.

use geardyn_io::checkpoint::Checkpoint;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Rec {
    a: u32,
    s: String,
}

fn rec(a: u32) -> Rec {
    Rec {
        a,
        s: format!("r{a}"),
    }
}

fn line(a: u32) -> String {
    Checkpoint::line(&rec(a))
}

const KEY: &str = r#"{"kind":"test","settings":{"n":3}}"#;

struct Dir(PathBuf);
impl Dir {
    fn new(name: &str) -> Self {
        let d = std::env::temp_dir().join(format!("geardyn-cp-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        Dir(d)
    }
    fn file(&self) -> PathBuf {
        self.0.join("checkpoint.jsonl")
    }
}
impl Drop for Dir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A store's text: the key line, then the lines of records `recs`.
fn store(recs: &[u32]) -> String {
    format!("{KEY}\n") + &recs.iter().map(|&a| line(a)).collect::<String>()
}

fn write(path: &Path, bytes: &[u8]) {
    std::fs::write(path, bytes).unwrap();
}

fn no_temp_left(dir: &Dir) {
    let names: Vec<_> = std::fs::read_dir(&dir.0)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    assert!(!names.iter().any(|n| n.ends_with(".tmp")), "{names:?}");
}

#[test]
fn records_survive_a_reopen_without_rewrite() {
    let dir = Dir::new("reopen");
    let p = dir.file();
    let (cp, done) = Checkpoint::open::<Rec>(&p, KEY).unwrap();
    assert!(done.is_empty());
    cp.append(&rec(1)).unwrap();
    cp.append(&rec(2)).unwrap();
    drop(cp);
    let before = std::fs::read(&p).unwrap();
    assert_eq!(before, store(&[1, 2]).into_bytes());
    let (cp, done) = Checkpoint::open::<Rec>(&p, KEY).unwrap();
    assert_eq!(done, vec![rec(1), rec(2)]);
    assert_eq!(cp.dropped(), 0);
    assert_eq!(std::fs::read(&p).unwrap(), before);
    no_temp_left(&dir);
}

#[test]
fn torn_last_line_is_dropped_and_appends_continue_on_a_new_line() {
    let dir = Dir::new("torn");
    let p = dir.file();
    write(&p, (store(&[1, 2]) + "{\"a\":3,\"s\":\"r").as_bytes());
    let (cp, done) = Checkpoint::open::<Rec>(&p, KEY).unwrap();
    assert_eq!(done, vec![rec(1), rec(2)]);
    assert_eq!(cp.dropped(), 1);
    cp.append(&rec(3)).unwrap();
    drop(cp);
    assert_eq!(std::fs::read_to_string(&p).unwrap(), store(&[1, 2, 3]));
    let (_, done) = Checkpoint::open::<Rec>(&p, KEY).unwrap();
    assert_eq!(done, vec![rec(1), rec(2), rec(3)]);
    no_temp_left(&dir);
}

#[test]
fn a_complete_last_record_without_newline_is_kept() {
    let dir = Dir::new("nonl");
    let p = dir.file();
    let l2 = line(2);
    write(&p, (store(&[1]) + l2.trim_end()).as_bytes());
    let (cp, done) = Checkpoint::open::<Rec>(&p, KEY).unwrap();
    assert_eq!(done, vec![rec(1), rec(2)]);
    assert_eq!(cp.dropped(), 0);
    cp.append(&rec(3)).unwrap();
    drop(cp);
    let (_, done) = Checkpoint::open::<Rec>(&p, KEY).unwrap();
    assert_eq!(done, vec![rec(1), rec(2), rec(3)]);
}

#[test]
fn reading_goes_on_past_non_utf8_and_damaged_lines() {
    let dir = Dir::new("bad");
    let p = dir.file();
    let mut bytes = store(&[1]).into_bytes();
    bytes.extend_from_slice(b"\xff\xfe\x00garbage\xc3\n");
    bytes.extend_from_slice(line(2).as_bytes());
    bytes.extend_from_slice(b"{\"a\": \"not a number\"}\n");
    bytes.extend_from_slice(b"\n");
    bytes.extend_from_slice(line(3).as_bytes());
    bytes.extend_from_slice(format!("{}\r\n", line(4).trim_end()).as_bytes());
    // valid JSON with a wrong checksum (a flipped digit) is not trusted
    bytes.extend_from_slice(line(5).replace("r5", "r6").as_bytes());
    write(&p, &bytes);
    let (cp, done) = Checkpoint::open::<Rec>(&p, KEY).unwrap();
    assert_eq!(done, vec![rec(1), rec(2), rec(3), rec(4)]);
    assert_eq!(cp.dropped(), 3);
    drop(cp);
    // rewritten with the good records only
    assert_eq!(std::fs::read_to_string(&p).unwrap(), store(&[1, 2, 3, 4]));
}

#[test]
fn validation_drops_rejected_records() {
    let dir = Dir::new("validate");
    let p = dir.file();
    write(&p, store(&[1, 7, 2]).as_bytes());
    let (cp, done) = Checkpoint::open_validated::<Rec, _>(&p, KEY, |r| r.a < 5).unwrap();
    assert_eq!(done, vec![rec(1), rec(2)]);
    assert_eq!(cp.dropped(), 1);
    drop(cp);
    let (_, done) = Checkpoint::open::<Rec>(&p, KEY).unwrap();
    assert_eq!(done, vec![rec(1), rec(2)]);
}

#[test]
fn a_rewrite_replaces_the_file_by_rename_never_in_place() {
    let dir = Dir::new("rename");
    let p = dir.file();
    let original = store(&[1]) + "{torn";
    write(&p, original.as_bytes());
    // a second name for the original file: an in-place truncation would show through it
    let link = dir.0.join("link.jsonl");
    std::fs::hard_link(&p, &link).unwrap();
    #[cfg(unix)]
    let ino = |q: &Path| std::os::unix::fs::MetadataExt::ino(&std::fs::metadata(q).unwrap());
    #[cfg(unix)]
    let ino_before = ino(&p);
    let (cp, done) = Checkpoint::open::<Rec>(&p, KEY).unwrap();
    assert_eq!(done, vec![rec(1)]);
    cp.append(&rec(2)).unwrap();
    drop(cp);
    assert_eq!(std::fs::read_to_string(&link).unwrap(), original);
    assert_eq!(std::fs::read_to_string(&p).unwrap(), store(&[1, 2]));
    #[cfg(unix)]
    {
        assert_ne!(ino(&p), ino_before, "rewritten in place");
        // a clean reopen does not rewrite
        let ino_clean = ino(&p);
        let _ = Checkpoint::open::<Rec>(&p, KEY).unwrap();
        assert_eq!(ino(&p), ino_clean);
    }
    no_temp_left(&dir);
}

#[test]
fn a_checkpoint_of_another_run_is_set_aside() {
    let dir = Dir::new("foreign");
    let p = dir.file();
    let other = format!("{{\"kind\":\"other\"}}\n{}", line(1));
    write(&p, other.as_bytes());
    let (cp, done) = Checkpoint::open::<Rec>(&p, KEY).unwrap();
    assert!(done.is_empty());
    cp.append(&rec(5)).unwrap();
    drop(cp);
    assert_eq!(
        std::fs::read_to_string(dir.0.join("checkpoint.jsonl.old")).unwrap(),
        other
    );
    assert_eq!(std::fs::read_to_string(&p).unwrap(), store(&[5]));
    // a non-UTF-8 key line is another run's too
    write(&p, b"\xff\xff\n");
    let (_, done) = Checkpoint::open::<Rec>(&p, KEY).unwrap();
    assert!(done.is_empty());
    // ... set aside beside the first one, which is kept
    assert_eq!(
        std::fs::read(dir.0.join("checkpoint.jsonl.old.2")).unwrap(),
        b"\xff\xff\n"
    );
    assert_eq!(
        std::fs::read_to_string(dir.0.join("checkpoint.jsonl.old")).unwrap(),
        other
    );
    no_temp_left(&dir);
}

#[test]
fn concurrent_appends_are_whole_lines() {
    let dir = Dir::new("threads");
    let p = dir.file();
    let (cp, _) = Checkpoint::open::<Rec>(&p, KEY).unwrap();
    std::thread::scope(|s| {
        for k in 0..4u32 {
            let cp = &cp;
            s.spawn(move || {
                for j in 0..25 {
                    cp.append(&rec(100 * k + j)).unwrap();
                }
            });
        }
    });
    drop(cp);
    let (cp, mut done) = Checkpoint::open::<Rec>(&p, KEY).unwrap();
    assert_eq!(cp.dropped(), 0);
    done.sort_by_key(|r| r.a);
    let mut want: Vec<Rec> = (0..4u32)
        .flat_map(|k| (0..25).map(move |j| rec(100 * k + j)))
        .collect();
    want.sort_by_key(|r| r.a);
    assert_eq!(done, want);
}
