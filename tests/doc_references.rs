//! Every document the project cites exists in the repository: README, code comments, report
//! templates and docs/ never point a reader at a file they do not have.

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().to_string();
        if p.is_dir() {
            if name != "target" && name != "node_modules" && !name.starts_with('.') {
                files(&p, out);
            }
        } else if [".rs", ".md", ".sh", ".html", ".toml", ".py"]
            .iter()
            .any(|x| name.ends_with(x))
        {
            out.push(p);
        }
    }
}

/// Every file of the repository that may cite another: README.md and the sources, docs,
/// examples, scripts and tests.
fn documents(root: &Path) -> Vec<PathBuf> {
    let mut all = vec![root.join("README.md")];
    for d in [
        "crates", "docs", "examples", "scripts", "src", "tests", "python",
    ] {
        if root.join(d).is_dir() {
            files(&root.join(d), &mut all);
        }
    }
    all
}

/// References to markdown files (with an optional path) in a text.
fn md_references(text: &str) -> Vec<String> {
    let mut refs = Vec::new();
    let bytes = text.as_bytes();
    let mut i = 0;
    while let Some(pos) = text[i..].find(".md") {
        let end = i + pos + 3;
        let after = bytes.get(end).copied().unwrap_or(b' ');
        let mut start = i + pos;
        while start > 0 {
            let c = bytes[start - 1];
            if c.is_ascii_alphanumeric() || b"_-./".contains(&c) {
                start -= 1;
            } else {
                break;
            }
        }
        if !(after.is_ascii_alphanumeric() || after == b'_') && start < i + pos {
            refs.push(text[start..end].to_string());
        }
        i = end;
    }
    refs
}

#[test]
fn every_cited_document_is_in_the_repository() {
    let root = root();
    let all = documents(&root);
    let mut missing = Vec::new();
    for f in &all {
        let text = std::fs::read_to_string(f).unwrap_or_default();
        for r in md_references(&text) {
            let r = r.trim_start_matches("./").to_string();
            let here = f.parent().unwrap().join(&r);
            if !(root.join(&r).is_file() || here.is_file()) {
                missing.push(format!("{}: {r}", f.strip_prefix(&root).unwrap().display()));
            }
        }
        assert!(
            !text.contains(concat!("shared/", "MODEL"))
                && !text.contains(concat!("../shared/", "seeds")),
            "{} points outside the repository",
            f.display()
        );
    }
    assert!(
        missing.is_empty(),
        "dangling references:\n{}",
        missing.join("\n")
    );
}

#[test]
fn the_reference_scanner_finds_references() {
    assert_eq!(
        md_references("see docs/model.md §2 and (README.md)."),
        vec!["docs/model.md", "README.md"]
    );
}

/// References to example scripts and programs (`examples/NAME.py`, `examples/NAME.rs`, with an
/// optional path before) in a text.
fn example_references(text: &str) -> Vec<String> {
    let mut refs = Vec::new();
    for (pos, _) in text.match_indices("examples/") {
        let bytes = text.as_bytes();
        let mut start = pos;
        while start > 0
            && (bytes[start - 1].is_ascii_alphanumeric() || b"_-./".contains(&bytes[start - 1]))
        {
            start -= 1;
        }
        let mut end = pos + "examples/".len();
        while end < bytes.len()
            && (bytes[end].is_ascii_alphanumeric() || b"_-.".contains(&bytes[end]))
        {
            end += 1;
        }
        let r = text[start..end].trim_end_matches('.');
        if r.ends_with(".py") || r.ends_with(".rs") {
            refs.push(r.to_string());
        }
    }
    refs
}

#[test]
fn every_cited_example_is_in_the_repository() {
    let root = root();
    let all = documents(&root);
    let mut missing = Vec::new();
    // (this file's own examples of references are not citations)
    for f in all
        .iter()
        .filter(|f| !f.ends_with("tests/doc_references.rs"))
    {
        let text = std::fs::read_to_string(f).unwrap_or_default();
        for r in example_references(&text) {
            let here = f.parent().unwrap().join(&r);
            if !(root.join(&r).is_file() || here.is_file()) {
                missing.push(format!("{}: {r}", f.strip_prefix(&root).unwrap().display()));
            }
        }
    }
    assert!(missing.is_empty(), "cited examples missing: {missing:?}");
    assert_eq!(
        example_references("run `python python/examples/a.py --quick` or examples/b.rs."),
        vec!["python/examples/a.py", "examples/b.rs"]
    );
}
