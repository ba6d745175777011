//! Every file rollphase writes goes through `crates/output/src/output.rs` (ARCHITECTURE.md, "Output"): no other
//! module of the source may create, write, rename, copy, link or save a file itself. A writer
//! that opened its own file kept the promise "output files are never damaged" only if its author
//! remembered every case (devices, links, inputs, a full disk); this scan makes the next writer
//! go through the one layer that handles them all.

use std::path::Path;

#[path = "common/source.rs"]
mod source;
use source::{code_only, rust_files};

/// The calls that create or change a file, as they appear in Rust source.
const FORBIDDEN: &[&str] = &[
    "File::create",
    "File::options",
    "OpenOptions",
    "fs::write",
    "fs::rename",
    "fs::copy",
    "fs::hard_link",
    "fs::create_dir",
    "fs::set_permissions",
    "os::unix::fs::symlink",
    "set_len(",
    ".save(",
    ".save_with_format(",
    "save_buffer",
];

/// The one module allowed to write files.
const OUTPUT_LAYER: &str = "crates/output/src/output.rs";

/// Lines of `source` that write a file without the output layer: (line number, call).
fn direct_writes(source: &str) -> Vec<(usize, &'static str)> {
    let code = code_only(source);
    let mut hits = Vec::new();
    for (n, line) in code.lines().enumerate() {
        for pat in FORBIDDEN {
            let mut from = 0;
            while let Some(at) = line[from..].find(pat) {
                let start = from + at;
                // `OutputFile::create` is the layer's own API, not `File::create`.
                let prefixed = pat.starts_with(char::is_alphabetic)
                    && line[..start]
                        .chars()
                        .last()
                        .is_some_and(|c| c.is_alphanumeric() || c == '_');
                if !prefixed {
                    hits.push((n + 1, *pat));
                }
                from = start + pat.len();
            }
        }
    }
    hits
}

#[test]
fn only_the_output_layer_writes_files() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    // The physics core writes nothing at all; the Python module writes through the layer too.
    rust_files(&root.join("crates/core/src"), &mut files);
    rust_files(&root.join("crates/output/src"), &mut files);
    rust_files(&root.join("python/src"), &mut files);
    assert!(files.len() > 50, "the scan found the source");
    let mut offenders = Vec::new();
    for f in &files {
        let rel = f.strip_prefix(root).unwrap().to_string_lossy().into_owned();
        if rel == OUTPUT_LAYER {
            continue;
        }
        let text = std::fs::read_to_string(f).unwrap();
        for (line, call) in direct_writes(&text) {
            offenders.push(format!("{rel}:{line}: {call}"));
        }
    }
    assert!(
        offenders.is_empty(),
        "these write files without crate::output (stage, check inputs, keep devices and links): \n{}",
        offenders.join("\n")
    );
    // The layer itself is where the calls are.
    let layer = std::fs::read_to_string(root.join(OUTPUT_LAYER)).unwrap();
    assert!(!direct_writes(&layer).is_empty());
}

#[test]
fn the_scan_catches_each_way_of_writing_a_file() {
    let planted = [
        ("std::fs::write(p, text)?;", "fs::write"),
        ("let f = File::create(&p)?;", "File::create"),
        (
            "let f = std::fs::OpenOptions::new().write(true).open(p)?;",
            "OpenOptions",
        ),
        ("fs::rename(a, b)?;", "fs::rename"),
        ("std::fs::copy(a, b)?;", "fs::copy"),
        ("std::fs::create_dir_all(&d)?;", "fs::create_dir"),
        ("image.save(&path)?;", ".save("),
        ("img.save_with_format(&p, Png)?;", ".save_with_format("),
        ("std::fs::hard_link(a, b)?;", "fs::hard_link"),
        ("let s = \"//\"; std::fs::write(p, s)?;", "fs::write"),
        ("let s = r#\"a \" b\"#; fs::write(p, s)?;", "fs::write"),
        ("let c = '\"'; fs::write(p, \"x\")?;", "fs::write"),
    ];
    for (code, call) in planted {
        let hits = direct_writes(code);
        assert!(
            hits.iter().any(|(_, c)| *c == call),
            "{code:?} must be caught as {call}, got {hits:?}"
        );
    }
    // Named in a comment, a doc or a message, or the layer's own API: not a write.
    for code in [
        "// std::fs::write(p, text)",
        "/// File::create is not used here",
        "/* fs::rename(a, b) */ let x = 1;",
        "bail!(\"cannot fs::write {}\", p);",
        "let f = OutputFile::create(&p, &inputs)?;",
        "let f = crate::output::OutputFile::create(&p, &inputs)?;",
    ] {
        assert!(direct_writes(code).is_empty(), "{code:?} is not a write");
    }
}
