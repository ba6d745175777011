//! The layers of ARCHITECTURE.md, checked on the source of both crates (the root package and
//! crates/core): every `crate::` path a module names is
//! one its layer may import (downward only), the physics core names no GPU or window crate, and
//! nothing outside `src/cli` (and `main.rs`) names `crate::cli`. A new module must be added to
//! the table here and in ARCHITECTURE.md, so the map cannot drift from the code.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Each top-level module and the modules it may import, as in ARCHITECTURE.md. `render::types`
/// names the one part of `render` that `view` may use: the plain draw data.
const ALLOWED: &[(&str, &[&str])] = &[
    // Leaves: no other module of the crate.
    ("assets", &[]),
    ("colormap", &[]),
    ("numeric", &[]),
    ("output", &[]),
    // Writers over the output layer.
    ("png", &["output"]),
    ("clip", &["output"]),
    // The physics core.
    ("geometry", &["numeric"]),
    ("integrate", &["numeric"]),
    ("dynamics", &["geometry", "integrate", "numeric"]),
    (
        "analysis",
        &["geometry", "integrate", "dynamics", "numeric"],
    ),
    // Runs and scenes.
    (
        "simulate",
        &["geometry", "integrate", "dynamics", "analysis", "numeric"],
    ),
    (
        "scene",
        &[
            "geometry",
            "integrate",
            "dynamics",
            "analysis",
            "numeric",
            "simulate",
            "assets",
        ],
    ),
    (
        "sim",
        &[
            "geometry",
            "integrate",
            "dynamics",
            "analysis",
            "numeric",
            "simulate",
            "scene",
        ],
    ),
    // Charts and the paper's figures.
    ("plot", &["colormap", "assets", "output"]),
    (
        "figures",
        &[
            "geometry",
            "integrate",
            "dynamics",
            "analysis",
            "numeric",
            "simulate",
            "plot",
            "colormap",
            "assets",
            "output",
        ],
    ),
    // Draw data, pixels, front ends.
    (
        "view",
        &[
            "geometry",
            "integrate",
            "dynamics",
            "analysis",
            "numeric",
            "simulate",
            "scene",
            "sim",
            "colormap",
            "render::types",
        ],
    ),
    ("render", &["colormap", "assets"]),
    (
        "headless",
        &[
            "geometry",
            "integrate",
            "dynamics",
            "analysis",
            "numeric",
            "simulate",
            "scene",
            "sim",
            "view",
            "render",
            "png",
            "clip",
            "output",
        ],
    ),
    (
        "ui",
        &[
            "geometry",
            "integrate",
            "dynamics",
            "analysis",
            "numeric",
            "simulate",
            "scene",
            "sim",
            "view",
            "render",
            "png",
            "clip",
            "colormap",
            "assets",
            "output",
        ],
    ),
    ("app", &["scene", "sim", "view", "render", "ui", "png"]),
    // The command line may use everything.
    ("cli", &["*"]),
];

/// Modules that must build without the `render` and `app` features: no GPU, window or UI crate.
const NO_GPU: &[&str] = &[
    "assets",
    "colormap",
    "numeric",
    "output",
    "png",
    "clip",
    "geometry",
    "integrate",
    "dynamics",
    "analysis",
    "simulate",
    "scene",
    "sim",
    "plot",
    "figures",
];

/// The source folders of the workspace's crates: the root package and the physics core, whose
/// modules share one table (in the core, `crate::` is the core itself; in the root, `crate::x`
/// of a core module is its re-export).
fn source_roots() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    vec![root.join("src"), root.join("crates/core/src")]
}

/// Every (source root, file) pair of the workspace.
fn workspace_files() -> Vec<(PathBuf, PathBuf)> {
    let mut out = Vec::new();
    for src in source_roots() {
        let mut files = Vec::new();
        rust_files(&src, &mut files);
        out.extend(files.into_iter().map(|f| (src.clone(), f)));
    }
    out
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The top-level module a source file belongs to (`src/view/body.rs` → "view").
fn module_of(src: &Path, file: &Path) -> String {
    let rel = file.strip_prefix(src).unwrap();
    let first = rel
        .components()
        .next()
        .unwrap()
        .as_os_str()
        .to_string_lossy();
    first.trim_end_matches(".rs").to_string()
}

/// The code of a file without comments (so a doc that mentions `crate::cli` is no import).
fn code(text: &str) -> String {
    text.lines()
        .map(|l| match l.find("//") {
            Some(i) => &l[..i],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Every path a text names below `crate::`, to two levels (`crate::a::b::C` → "a::b",
/// `crate::a` → "a"), also inside `use crate::{a, b::c}`.
fn crate_paths(code: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect()
    };
    let mut rest = code;
    while let Some(i) = rest.find("crate::") {
        let after = &rest[i + "crate::".len()..];
        if let Some(group) = after.strip_prefix('{') {
            let end = group.find('}').unwrap_or(group.len());
            for item in group[..end].split(',') {
                let item = item.trim();
                let first = ident(item);
                if !first.is_empty() {
                    let second = item
                        .strip_prefix(&first)
                        .and_then(|s| s.strip_prefix("::"))
                        .map(ident)
                        .unwrap_or_default();
                    out.insert(if second.is_empty() {
                        first
                    } else {
                        format!("{first}::{second}")
                    });
                }
            }
        } else {
            let first = ident(after);
            let second = after[first.len()..]
                .strip_prefix("::")
                .map(ident)
                .unwrap_or_default();
            out.insert(if second.is_empty() {
                first
            } else {
                format!("{first}::{second}")
            });
        }
        rest = after;
    }
    out
}

#[test]
fn every_module_imports_only_the_layers_below_it() {
    let allowed: BTreeMap<&str, &[&str]> = ALLOWED.iter().copied().collect();
    let mut violations = Vec::new();
    let mut seen = BTreeSet::new();
    for (src, file) in &workspace_files() {
        let module = module_of(src, file);
        if module == "lib" || module == "main" {
            continue;
        }
        seen.insert(module.clone());
        let Some(may) = allowed.get(module.as_str()) else {
            violations.push(format!(
                "{}: module `{module}` is not in ARCHITECTURE.md's table (add it there and here)",
                file.display()
            ));
            continue;
        };
        if may.contains(&"*") {
            continue;
        }
        let text = code(&std::fs::read_to_string(file).unwrap());
        for path in crate_paths(&text) {
            let top = path.split("::").next().unwrap();
            // An entry like `render::types` allows that part only, not the rest of `render`.
            let ok = top == module || may.contains(&top) || may.contains(&path.as_str());
            if !ok {
                violations.push(format!(
                    "{}: `{module}` names `crate::{path}`",
                    file.display()
                ));
            }
        }
    }
    for (module, _) in ALLOWED {
        assert!(
            seen.contains(*module),
            "the table lists `{module}`, which is not a module any more"
        );
    }
    assert!(
        violations.is_empty(),
        "imports against the layers:\n{}",
        violations.join("\n")
    );
}

#[test]
fn the_physics_core_names_no_gpu_window_or_ui_crate() {
    let mut violations = Vec::new();
    for (src, file) in &workspace_files() {
        let module = module_of(src, file);
        if !NO_GPU.contains(&module.as_str()) {
            continue;
        }
        let text = code(&std::fs::read_to_string(file).unwrap());
        for krate in [
            "wgpu",
            "winit",
            "egui",
            "egui_wgpu",
            "egui_winit",
            "egui_plot",
            "pollster",
        ] {
            if text.contains(&format!("{krate}::")) || text.contains(&format!("use {krate}")) {
                violations.push(format!("{}: names {krate}", file.display()));
            }
        }
    }
    assert!(violations.is_empty(), "{}", violations.join("\n"));
}

#[test]
fn the_import_checker_sees_grouped_and_nested_paths() {
    let paths =
        crate_paths("use crate::{geometry::Body, cli};\nlet x = crate::render::types::Frame;");
    let want: BTreeSet<String> = ["geometry::Body", "cli", "render::types"]
        .into_iter()
        .map(String::from)
        .collect();
    assert_eq!(paths, want);
    assert_eq!(code("let a = 1; // crate::cli"), "let a = 1; ");
}
