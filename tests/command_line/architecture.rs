//! The layers of ARCHITECTURE.md, checked on the source of the Rust crates (the root package,
//! crates/core and crates/output): every path a module names into the crate (`crate::…`, grouped and nested uses,
//! and `super::` chains that climb to the crate root) is one its layer may import, as the
//! "Allowed imports" table of ARCHITECTURE.md says (read from the file, so the map cannot drift
//! from the code); the physics core names no GPU or window crate; nothing outside `src/cli` (and
//! `main.rs`) names `crate::cli`. Comments and string literals are blanked before the scan.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use crate::source::{code_only, rust_files};

/// The physics core's modules, which "the core" stands for in the table.
const CORE: [&str; 5] = ["geometry", "integrate", "dynamics", "analysis", "numeric"];

/// The "Allowed imports" table of an ARCHITECTURE.md text: each module (left cell, in backticks)
/// and what it may import (the right cell's backticked names; "the core" adds the core's five,
/// "everything" allows all, "nothing" none). `render::types` in a cell allows that part only.
fn allowed_table(md: &str) -> BTreeMap<String, Vec<String>> {
    let section = md
        .split("## Allowed imports")
        .nth(1)
        .expect("ARCHITECTURE.md has an \"Allowed imports\" section");
    let mut table = BTreeMap::new();
    for line in section.lines().skip_while(|l| !l.starts_with('|')) {
        if !line.starts_with('|') {
            break;
        }
        let cells: Vec<&str> = line.split('|').collect();
        if cells.len() < 3 || !cells[1].contains('`') {
            continue;
        }
        let right = cells[2];
        let may: Vec<String> = if right.contains("everything") {
            vec!["*".into()]
        } else {
            let mut v: Vec<String> = backticked(right)
                .into_iter()
                .filter(|n| !n.starts_with("crate::"))
                .collect();
            if right.contains("the core") {
                v.extend(CORE.iter().map(|m| m.to_string()));
            }
            v
        };
        for module in backticked(cells[1]) {
            table.insert(module, may.clone());
        }
    }
    table
}

/// The `backticked` words of a table cell.
fn backticked(cell: &str) -> Vec<String> {
    cell.split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

fn architecture_table() -> BTreeMap<String, Vec<String>> {
    let md = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("ARCHITECTURE.md"))
        .expect("ARCHITECTURE.md");
    allowed_table(&md)
}

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
    "live",
    "chart",
    "figures",
    "fit_lag",
];

/// The source folders of the workspace's Rust crates (all but `python/`), whose modules share
/// one table: in each crate `crate::x` is its own module or its re-export of another crate's.
fn source_roots() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    vec![
        root.join("src"),
        root.join("crates/core/src"),
        root.join("crates/output/src"),
        root.join("crates/assets/src"),
        root.join("crates/scene/src"),
        root.join("crates/figures/src"),
        root.join("crates/viewer/src"),
    ]
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

fn ident(s: &str) -> String {
    s.chars()
        .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
        .collect()
}

/// The items of a `{…}` group that starts at `text` (just after the `{`), split at its own
/// top-level commas (nested groups kept whole), and the rest after the closing brace.
fn group_items(text: &str) -> (Vec<&str>, &str) {
    let (mut depth, mut start, mut items) = (0usize, 0usize, Vec::new());
    for (i, c) in text.char_indices() {
        match c {
            '{' => depth += 1,
            '}' if depth == 0 => {
                items.push(&text[start..i]);
                return (items, &text[i + 1..]);
            }
            '}' => depth -= 1,
            ',' if depth == 0 => {
                items.push(&text[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    items.push(&text[start..]);
    (items, "")
}

/// The paths (to two levels, `a::b`, or `a`) that `path` names below the crate root; `path` is
/// what follows `crate::`, e.g. `a::b::C`, `{a::X, b::{Y, Z}}` or `a::{b, c}`.
fn paths_below_root(path: &str, out: &mut BTreeSet<String>) {
    let path = path.trim_start();
    if let Some(group) = path.strip_prefix('{') {
        for item in group_items(group).0 {
            paths_below_root(item, out);
        }
        return;
    }
    let first = ident(path);
    if first.is_empty() {
        return;
    }
    let rest = path[first.len()..].trim_start();
    match rest.strip_prefix("::").map(str::trim_start) {
        Some(r) if r.starts_with('{') => {
            for item in group_items(&r[1..]).0 {
                let second = ident(item.trim_start());
                out.insert(if second.is_empty() || second == "self" {
                    first.clone()
                } else {
                    format!("{first}::{second}")
                });
            }
        }
        Some(r) => {
            let second = ident(r);
            out.insert(if second.is_empty() {
                first
            } else {
                format!("{first}::{second}")
            });
        }
        None => {
            out.insert(first);
        }
    }
}

/// Every path below the crate root that `code` (comments and strings already blanked) names:
/// through `crate::`, and through `super::` chains that climb out of `module` (the file's module
/// path, e.g. `["view", "body"]`) and of the inline `mod x { … }` blocks around them to the
/// root.
fn crate_paths_in(code: &str, module: &[String]) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let text = code;
    // Inline modules around the current character: the brace depth each opened at.
    let mut inline: Vec<usize> = Vec::new();
    let mut depth = 0usize;
    let mut pending_mod = false;
    let chars: Vec<(usize, char)> = text.char_indices().collect();
    let mut k = 0;
    while k < chars.len() {
        let (at, c) = chars[k];
        let rest = &text[at..];
        let boundary = at == 0 || !text[..at].ends_with(|p: char| p.is_alphanumeric() || p == '_');
        if boundary && rest.starts_with("mod ") {
            let name = ident(rest[4..].trim_start());
            let after = rest[4..].trim_start()[name.len()..].trim_start();
            pending_mod = !name.is_empty() && after.starts_with('{');
        }
        match c {
            '{' => {
                depth += 1;
                if pending_mod {
                    inline.push(depth);
                    pending_mod = false;
                }
            }
            '}' => {
                if inline.last() == Some(&depth) {
                    inline.pop();
                }
                depth = depth.saturating_sub(1);
            }
            _ => {}
        }
        if boundary && rest.starts_with("crate::") {
            paths_below_root(&rest["crate::".len()..], &mut out);
        } else if boundary && rest.starts_with("super::") {
            let mut climbs = 0;
            let mut r = rest;
            while let Some(next) = r.strip_prefix("super::") {
                climbs += 1;
                r = next.trim_start();
            }
            let here = module.len() + inline.len();
            if climbs >= here {
                // At the crate root: what follows is a top-level module.
                paths_below_root(r, &mut out);
            } else if climbs >= inline.len() {
                // Inside the file's own module path: `super::…` lands in module[..here - climbs].
                let landing = &module[..here - climbs];
                if let Some(top) = landing.first() {
                    out.insert(top.clone());
                }
            }
            // Skip the chain just read.
            let skip = rest.len() - r.len();
            let target = at + skip;
            while k < chars.len() && chars[k].0 < target {
                k += 1;
            }
            continue;
        }
        k += 1;
    }
    out
}

/// The module path of a source file (`src/view/body.rs` → view::body, `src/view/mod.rs` →
/// view, `src/app.rs` → app).
fn module_path(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap();
    let mut parts: Vec<String> = rel
        .components()
        .map(|c| {
            c.as_os_str()
                .to_string_lossy()
                .trim_end_matches(".rs")
                .to_string()
        })
        .collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    parts
}

/// Where `file` may not reach: `(path, why)` for each path it names against `table`.
fn violations_in(
    table: &BTreeMap<String, Vec<String>>,
    module_path: &[String],
    code: &str,
) -> Result<Vec<String>, String> {
    let module = module_path.first().cloned().unwrap_or_default();
    let Some(may) = table.get(&module) else {
        return Err(format!(
            "module `{module}` is not in ARCHITECTURE.md's \"Allowed imports\" table (add it there)"
        ));
    };
    if may.iter().any(|m| m == "*") {
        return Ok(Vec::new());
    }
    Ok(crate_paths_in(code, module_path)
        .into_iter()
        .filter(|path| {
            let top = path.split("::").next().unwrap_or("");
            // An entry like `render::types` allows that part only, not the rest of `render`.
            !(top == module || may.iter().any(|m| m == top || m == path))
        })
        .collect())
}

#[test]
fn every_module_imports_only_the_layers_below_it() {
    let table = architecture_table();
    assert!(table.len() > 20, "the table was read: {table:?}");
    let mut violations = Vec::new();
    let mut seen = BTreeSet::new();
    for (src, file) in &workspace_files() {
        let module = module_of(src, file);
        if module == "lib" || module == "main" {
            continue;
        }
        seen.insert(module.clone());
        let code = code_only(&std::fs::read_to_string(file).unwrap());
        match violations_in(&table, &module_path(src, file), &code) {
            Err(e) => violations.push(format!("{}: {e}", file.display())),
            Ok(paths) => violations.extend(
                paths
                    .into_iter()
                    .map(|p| format!("{}: `{module}` names `crate::{p}`", file.display())),
            ),
        }
    }
    for module in table.keys() {
        assert!(
            seen.contains(module),
            "ARCHITECTURE.md's table lists `{module}`, which is not a module any more"
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
        let text = code_only(&std::fs::read_to_string(file).unwrap());
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

fn set(items: &[&str]) -> BTreeSet<String> {
    items.iter().map(|s| s.to_string()).collect()
}

fn path(parts: &[&str]) -> Vec<String> {
    parts.iter().map(|s| s.to_string()).collect()
}

#[test]
fn the_import_checker_sees_grouped_and_nested_paths() {
    let paths = crate_paths_in(
        &code_only("use crate::{geometry::Body, cli};\nlet x = crate::render::types::Frame;"),
        &path(&["view"]),
    );
    assert_eq!(paths, set(&["geometry::Body", "cli", "render::types"]));
    // A nested group names both of its modules, not only the first.
    let nested = crate_paths_in(
        &code_only("use crate::{sim::{Snapshot, SimStatus}, ui::Workbench};"),
        &path(&["view"]),
    );
    assert_eq!(
        nested,
        set(&["sim::Snapshot", "sim::SimStatus", "ui::Workbench"])
    );
    let inner = crate_paths_in(
        &code_only("use crate::live::{self, Snapshot};"),
        &path(&["x"]),
    );
    assert_eq!(inner, set(&["live", "live::Snapshot"]));
}

#[test]
fn the_import_checker_is_not_fooled_by_super_chains_strings_or_comments() {
    // `super::super` from view/body.rs climbs to the crate root: that is `crate::live`.
    let up = crate_paths_in(
        &code_only("use super::super::live::Snapshot;"),
        &path(&["view", "body"]),
    );
    assert_eq!(up, set(&["live::Snapshot"]));
    // One `super` from view/body.rs stays in view: not an import of another module.
    let sibling = crate_paths_in(
        &code_only("use super::layout::Layout;"),
        &path(&["view", "body"]),
    );
    assert_eq!(sibling, set(&["view"]));
    // Inside an inline `mod tests { … }`, `super::super` from view/body.rs is only view.
    let tests = crate_paths_in(
        &code_only("mod tests {\n    use super::super::layout::X;\n}\nuse super::super::ui::Y;"),
        &path(&["view", "body"]),
    );
    assert_eq!(tests, set(&["view", "ui::Y"]));
    // A `//` inside a string does not hide the code after it; a path in a comment or a string
    // is not an import.
    let after_string = crate_paths_in(
        &code_only("let url = \"http://x\"; let s = crate::cli::Cli::parse();"),
        &path(&["sim"]),
    );
    assert_eq!(after_string, set(&["cli::Cli"]));
    let quiet = crate_paths_in(
        &code_only("// crate::cli\n/// [`crate::ui`]\nlet m = \"crate::app\";"),
        &path(&["sim"]),
    );
    assert!(quiet.is_empty(), "{quiet:?}");
    // And each of these is a violation for `sim`, whose row does not allow cli or ui.
    let table = allowed_table(
        "## Allowed imports\n\n| module | may import |\n|---|---|\n| `sim` | the core, `simulate` |\n| `view` | `sim`, of `render` only `render::types` |\n| `cli` | everything; nothing else names `crate::cli` |\n",
    );
    assert_eq!(table["sim"].len(), 6, "{table:?}");
    assert_eq!(table["cli"], ["*"]);
    assert!(table["view"].contains(&"render::types".to_string()));
    let bad = violations_in(
        &table,
        &path(&["sim", "thread"]),
        &code_only("use super::super::cli::X;\nlet s = \"//\"; crate::ui::Y;"),
    )
    .unwrap();
    assert_eq!(bad, ["cli::X", "ui::Y"]);
    assert!(violations_in(&table, &path(&["nowhere"]), "").is_err());
}

/// The rules clippy enforces for the whole workspace (clippy.toml, `[workspace.lints]`), kept
/// from being weakened unnoticed: every way of writing a file is a disallowed method, only the
/// output layer (and the tests' fixtures) allow them, and a function over 150 lines needs
/// `#[expect(clippy::too_many_lines, reason = "…")]`. `.ci/run` runs clippy with `-D warnings`.
#[test]
fn clippy_refuses_file_writes_outside_the_output_layer_and_unexplained_long_functions() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config: toml::Table =
        toml::from_str(&std::fs::read_to_string(root.join("clippy.toml")).unwrap()).unwrap();
    let disallowed: BTreeSet<&str> = config["disallowed-methods"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["path"].as_str().unwrap())
        .collect();
    for write in [
        "std::fs::write",
        "std::fs::File::create",
        "std::fs::File::create_new",
        "std::fs::File::options",
        "std::fs::File::set_len",
        "std::fs::OpenOptions::open",
        "std::fs::rename",
        "std::fs::copy",
        "std::fs::hard_link",
        "std::fs::create_dir",
        "std::fs::create_dir_all",
        "std::fs::set_permissions",
        "std::os::unix::fs::symlink",
        "image::ImageBuffer::save",
        "image::DynamicImage::save",
        "image::save_buffer",
    ] {
        assert!(
            disallowed.contains(write),
            "clippy.toml no longer refuses {write}"
        );
    }
    assert_eq!(config["too-many-lines-threshold"].as_integer(), Some(150));
    let manifest: toml::Table =
        toml::from_str(&std::fs::read_to_string(root.join("Cargo.toml")).unwrap()).unwrap();
    assert_eq!(
        manifest["workspace"]["lints"]["clippy"]["too_many_lines"].as_str(),
        Some("warn")
    );
    for member in workspace_manifests() {
        let m: toml::Table = toml::from_str(&std::fs::read_to_string(&member).unwrap()).unwrap();
        assert_eq!(
            m.get("lints")
                .and_then(|l| l.get("workspace"))
                .and_then(|w| w.as_bool()),
            Some(true),
            "{} takes the workspace's lints",
            member.display()
        );
    }
    // Only the output layer's crate root lifts the rule in the source (the tests' binaries lift
    // it for their fixtures).
    let mut files: Vec<PathBuf> = workspace_files().into_iter().map(|(_, f)| f).collect();
    rust_files(&root.join("python/src"), &mut files);
    let lifted: Vec<String> = files
        .iter()
        .filter(|f| {
            code_only(&std::fs::read_to_string(f).unwrap()).contains("clippy::disallowed_methods")
        })
        .map(|f| f.strip_prefix(root).unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(lifted, ["crates/output/src/lib.rs"]);
}

/// The Cargo.toml of every member of the workspace.
fn workspace_manifests() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let manifest: toml::Table =
        toml::from_str(&std::fs::read_to_string(root.join("Cargo.toml")).unwrap()).unwrap();
    manifest["workspace"]["members"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| root.join(m.as_str().unwrap()).join("Cargo.toml"))
        .collect()
}

/// The public functions (`pub fn`, at any indentation) of a source text whose doc holds no
/// example (a fenced code block), with their lines; the text's tests (from `#[cfg(test)]` at
/// the start of a line) are not looked at.
fn public_functions_without_example(text: &str) -> Vec<(String, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        if line.starts_with("#[cfg(test)]") {
            break;
        }
        let Some(rest) = line.trim_start().strip_prefix("pub fn ") else {
            continue;
        };
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        let doc = lines[..i]
            .iter()
            .rev()
            .take_while(|l| {
                let l = l.trim_start();
                l.starts_with("///") || l.starts_with("#[")
            })
            .any(|l| l.contains("```"));
        if !doc {
            out.push((name, i + 1));
        }
    }
    out
}

#[test]
fn every_public_function_of_the_core_has_an_example() {
    let core = Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/core/src");
    let mut files = Vec::new();
    rust_files(&core, &mut files);
    let mut missing = Vec::new();
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        for (name, line) in public_functions_without_example(&text) {
            missing.push(format!("{}:{line} fn {name}", file.display()));
        }
    }
    assert!(
        missing.is_empty(),
        "give these an example in their doc (run as a doctest):\n{}",
        missing.join("\n")
    );
}

#[test]
fn the_example_check_reads_docs_and_attributes_and_skips_tests() {
    let text = "/// Doubles.\n///\n/// ```\n/// assert_eq!(f(1), 2);\n/// ```\n#[must_use]\npub fn f(x: i32) -> i32 {\n    2 * x\n}\n\nimpl A {\n    /// No example.\n    pub fn g(&self) {}\n    pub(crate) fn h() {}\n}\n#[cfg(test)]\nmod tests {\n    pub fn helper() {}\n}\n";
    assert_eq!(
        public_functions_without_example(text),
        vec![("g".to_string(), 13)]
    );
}

/// ARCHITECTURE.md's module table names every source file of each module whose row lists its
/// files, and no file that is gone (`sim::history`, `ui::sweep` and `ui::fonts` went missing
/// from it once). A row that says "one file per …" gives a rule instead of a list.
/// The module paths (`["scene", "setup", "SceneSetup"]`) that `code` names through `crate::`
/// and through `super::` chains from `module` (the file's module path). Test modules are left
/// out: they follow `#[cfg(test)]` at the end of a file and reach their parent by `super::*`.
fn named_paths(code: &str, module: &[String]) -> Vec<Vec<String>> {
    let code = code.split("#[cfg(test)]").next().unwrap_or(code);
    let mut out = Vec::new();
    let mut at = 0;
    while at < code.len() {
        let rest = &code[at..];
        let boundary =
            at == 0 || !code[..at].ends_with(|p: char| p.is_alphanumeric() || p == '_' || p == ':');
        let start = if boundary && rest.starts_with("crate::") {
            Some((Vec::new(), &rest["crate::".len()..]))
        } else if boundary && rest.starts_with("super::") {
            let mut climbs = 0;
            let mut r = rest;
            while let Some(next) = r.strip_prefix("super::") {
                climbs += 1;
                r = next.trim_start();
            }
            // A mod.rs is its module: `super` from view/mod.rs is the crate root.
            Some((module[..module.len().saturating_sub(climbs)].to_vec(), r))
        } else {
            None
        };
        if let Some((base, path)) = start {
            expand_path(base, path, &mut out);
        }
        at += rest.chars().next().map_or(1, char::len_utf8);
    }
    out
}

/// `base` followed by each path `text` names (`a::b`, `a::{b, c::D}`), into `out`.
fn expand_path(base: Vec<String>, text: &str, out: &mut Vec<Vec<String>>) {
    let mut path = base;
    let mut rest = text.trim_start();
    loop {
        if let Some(group) = rest.strip_prefix('{') {
            for item in group_items(group).0 {
                expand_path(path.clone(), item, out);
            }
            return;
        }
        let name = ident(rest);
        if name.is_empty() {
            break;
        }
        path.push(name.clone());
        rest = rest[name.len()..].trim_start();
        match rest.strip_prefix("::") {
            Some(r) => rest = r.trim_start(),
            None => break,
        }
    }
    out.push(path);
}

/// Pairs of source files of one crate that each name the other, as "a.rs ↔ b.rs".
fn two_file_circles(files: &[(Vec<String>, String)], name: &str) -> Vec<String> {
    let known: BTreeSet<&Vec<String>> = files.iter().map(|(m, _)| m).collect();
    let mut edges = BTreeSet::new();
    for (module, code) in files {
        for path in named_paths(code, module) {
            // The longest prefix that is a file of the crate.
            let target = (1..=path.len())
                .rev()
                .map(|n| path[..n].to_vec())
                .find(|p| known.contains(p));
            if let Some(target) = target
                && &target != module
            {
                edges.insert((module.clone(), target));
            }
        }
    }
    edges
        .iter()
        .filter(|(a, b)| a < b && edges.contains(&(b.clone(), a.clone())))
        .map(|(a, b)| format!("{name}: {} ↔ {}", a.join("::"), b.join("::")))
        .collect()
}

/// The two-file circles left, each with its reason. Anything else fails
/// [`no_two_files_import_each_other`].
const KNOWN_CIRCLES: &[(&str, &str)] = &[
    (
        "geometry::disk ↔ geometry::hull",
        "a disk caches its convex hull (computed once, on the first run of a dented body), and \
         the hull is computed from the disk's r(θ)",
    ),
    (
        "figures ↔ figures::shard",
        "the shard runner (shard::ensemble) runs a figure's ensemble by the figure registry and \
         FigureOptions, and each figure runs its ensemble through the shard runner",
    ),
];

/// No two files import each other beyond [`KNOWN_CIRCLES`] (three such circles were broken on
/// 2026-11-25: `cli::app` ↔ `cli::render`, `scene::setup` ↔ `scene::timeline`,
/// `integrate::lie` ↔ `integrate::rk4`); a shared piece goes to a third file both import.
#[test]
fn no_two_files_import_each_other() {
    let mut circles = Vec::new();
    let mut files_seen = 0;
    for src in source_roots() {
        let mut files = Vec::new();
        rust_files(&src, &mut files);
        let parsed: Vec<(Vec<String>, String)> = files
            .iter()
            .map(|f| {
                (
                    module_path(&src, f),
                    code_only(&std::fs::read_to_string(f).unwrap()),
                )
            })
            .collect();
        files_seen += parsed.len();
        circles.extend(two_file_circles(&parsed, &src.display().to_string()));
    }
    assert!(
        files_seen > 100,
        "the scan found the source ({files_seen} files)"
    );
    let unexplained: Vec<&String> = circles
        .iter()
        .filter(|c| {
            !KNOWN_CIRCLES
                .iter()
                .any(|(k, _)| c.ends_with(&format!(": {k}")))
        })
        .collect();
    assert!(
        unexplained.is_empty(),
        "files that import each other (break the circle, or add it to KNOWN_CIRCLES with \
         its reason):\n{unexplained:?}"
    );
    // A circle that was broken leaves the list.
    for (known, _) in KNOWN_CIRCLES {
        assert!(
            circles.iter().any(|c| c.ends_with(&format!(": {known}"))),
            "{known} is no longer a circle: remove it from KNOWN_CIRCLES"
        );
    }
}

#[test]
fn the_circle_check_sees_crate_and_super_paths_both_ways() {
    let file = |m: &[&str], code: &str| (path(m), code_only(code));
    let circle = [
        file(&["scene", "setup"], "use super::timeline::Step;"),
        file(
            &["scene", "timeline"],
            "fn f() { crate::scene::setup::check(); }",
        ),
        file(&["scene"], "pub mod setup; pub mod timeline;"),
    ];
    assert_eq!(
        two_file_circles(&circle, "x"),
        ["x: scene::setup ↔ scene::timeline"]
    );
    // One way only, a grouped import, a test module's super::*, a comment: no circle.
    let fine = [
        file(&["a"], "use crate::{b::{X, Y}, c};"),
        file(
            &["b"],
            "// crate::a::z\n#[cfg(test)]\nmod tests { use super::*; use crate::a::Q; }",
        ),
    ];
    assert!(two_file_circles(&fine, "x").is_empty());
}

#[test]
fn the_module_table_names_every_source_file_of_each_module() {
    let md = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("ARCHITECTURE.md"))
        .expect("ARCHITECTURE.md");
    let start = md
        .find("## Modules and what they own")
        .expect("the module table");
    let end = md[start..]
        .find("\n## ")
        .map_or(md.len(), |i| start + 1 + i);
    let mut checked = 0;
    for line in md[start..end].lines().filter(|l| l.starts_with("| `")) {
        let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
        let module = backticked(cells[0]).remove(0);
        let files_cell = cells[cells.len() - 1];
        if files_cell.contains("one file per") {
            continue;
        }
        let listed: BTreeSet<String> = backticked(files_cell)
            .into_iter()
            // File names only: lower-case words (a cell also names types, `SceneError`).
            .filter(|n| {
                n.chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
            })
            .collect();
        for root in source_roots() {
            let dir = root.join(&module);
            if !dir.is_dir() {
                continue;
            }
            // Files in the module's sub-folders count too (`analysis/orbits/disk_period.rs`).
            let mut files = Vec::new();
            rust_files(&dir, &mut files);
            let stems: BTreeSet<String> = files
                .iter()
                .filter_map(|f| f.file_stem().map(|s| s.to_string_lossy().into_owned()))
                .filter(|s| s != "mod")
                .collect();
            let missing: Vec<&String> = stems.difference(&listed).collect();
            assert!(
                missing.is_empty(),
                "ARCHITECTURE.md's row for `{module}` does not name {missing:?}"
            );
            let gone: Vec<&String> = listed
                .iter()
                .filter(|n| *n != "mod" && !stems.contains(*n))
                .collect();
            assert!(
                gone.is_empty(),
                "ARCHITECTURE.md's row for `{module}` names {gone:?}, which {} has not",
                dir.display()
            );
            checked += 1;
        }
    }
    assert!(checked >= 10, "{checked} modules checked");
}

/// One model choice: which model a run gets is decided by `dynamics::models`
/// (`ModelKind::of`, `for_dimension`, `asks_for_inertia`), never by an m/m0 compared with 0
/// elsewhere (issue 44 found it in 29 places). The comparisons left compare a value, not a
/// model: each is listed with its reason.
#[test]
fn the_model_is_chosen_in_one_place() {
    const VALUE_CHECKS: &[(&str, &str)] = &[
        ("crates/core/src/dynamics/models.rs", "the one rule"),
        (
            "crates/core/src/dynamics/mod.rs",
            "Ramp::with_drag refuses zero drag where no inertia bounds the speed",
        ),
        (
            "crates/core/src/simulate/typed.rs",
            "an input check: m/m0 finite and > 0 for Model::Inertial",
        ),
        (
            "crates/viewer/src/ui/measuring_sweep.rs",
            "a sweep in m/m0 starting from 0 takes its first value",
        ),
        (
            "crates/viewer/src/ui/mod.rs",
            "a sweep in m/m0 starting from 0 takes its first value",
        ),
    ];
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files: Vec<PathBuf> = workspace_files().into_iter().map(|(_, f)| f).collect();
    rust_files(&root.join("python/src"), &mut files);
    let compared = |text: &str| {
        ["mass_ratio", "mass", "model_mass"].iter().any(|name| {
            ["== 0.0", "> 0.0", "<= 0.0", "!= 0.0"]
                .iter()
                .any(|op| text.contains(&format!("{name} {op}")))
        }) || text.contains(".is_viscous()")
    };
    let mut violations = Vec::new();
    for file in &files {
        let rel = file
            .strip_prefix(root)
            .unwrap()
            .to_string_lossy()
            .into_owned();
        let text = code_only(&std::fs::read_to_string(file).unwrap());
        let text = text.split("#[cfg(test)]").next().unwrap_or(&text);
        if compared(text) && !VALUE_CHECKS.iter().any(|(f, _)| *f == rel) {
            violations.push(rel);
        }
    }
    assert!(
        violations.is_empty(),
        "choose the model through dynamics::models (ModelKind::of, asks_for_inertia), not by \
         comparing m/m0 with 0:\n{}",
        violations.join("\n")
    );
    assert!(compared("if a.mass > 0.0 {") && compared("ramp.is_viscous()"));
}

/// Longest source file (lines) anywhere in the crates, and in the command line (`src/cli`, which
/// only parses and prints): past these a file mixes concepts and is split by concept (issue 58).
const MAX_SOURCE_LINES: usize = 1000;
const MAX_CLI_LINES: usize = 700;

#[test]
fn no_source_file_is_over_its_length() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut roots = source_roots();
    roots.push(root.join("python/src"));
    let mut long = Vec::new();
    for src in roots {
        let mut files = Vec::new();
        rust_files(&src, &mut files);
        for f in files {
            let lines = std::fs::read_to_string(&f).unwrap().lines().count();
            let limit = if f.starts_with(root.join("src/cli")) {
                MAX_CLI_LINES
            } else {
                MAX_SOURCE_LINES
            };
            if lines > limit {
                long.push(format!(
                    "{} has {lines} lines (at most {limit})",
                    f.strip_prefix(root).unwrap().display()
                ));
            }
        }
    }
    assert!(long.is_empty(), "split by concept: {long:#?}");
    // The check sees the files: the core is there and counted.
    let mut core = Vec::new();
    rust_files(&root.join("crates/core/src"), &mut core);
    assert!(core.len() > 50, "{} core files", core.len());
}
