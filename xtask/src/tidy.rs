//! Tidy tests: the invariants of `docs/ARCHITECTURE.md`, checked on the source tree by
//! `cargo test -p xtask` (part of `cargo xtask test`). Each invariant of the doc names the test
//! here that holds it, and [`every_invariant_of_the_doc_names_its_tidy_test`] keeps the two
//! together. They read files as text, without building anything, so a broken invariant is
//! found in a second.

use std::fs;
use std::path::{Path, PathBuf};

/// The architecture document.
const DOC: &str = "docs/ARCHITECTURE.md";

/// The most lines the architecture document may have: it is a map, not a manual.
const DOC_MAX_LINES: usize = 200;

/// The crates under `crates/` that are not detection methods: the layers every method shares,
/// the tools and the bindings. Every other crate there is a method crate.
const NOT_METHODS: &[&str] = &[
    "boundary",
    "boundary-core",
    "boundary-io",
    "boundary-sph",
    "boundary-resample",
    "boundary-cli",
    "boundary-scenes",
    "boundary-sweep",
    "boundary-svm-train",
    "boundary-mpi",
    "boundary-py",
    "boundary-capi",
];

/// The library crates besides the methods: they compute, and neither print nor touch a file.
const LIBRARIES: &[&str] = &[
    "boundary",
    "boundary-core",
    "boundary-sph",
    "boundary-resample",
];

/// The one place a library crate touches the file system, with why: the `svm` model file is
/// the method's parameter.
const FILE_SYSTEM_EXCEPTIONS: &[(&str, &str)] = &[("boundary-svm", "src/lib.rs")];

/// The lint line every library crate's root starts with: `clippy.toml` disallows the `std::fs`
/// functions and the file-system queries of `Path`, so clippy holds the invariant.
const NO_OUTPUT_NO_FILES: &str =
    "#![deny(clippy::print_stdout, clippy::print_stderr, clippy::disallowed_methods)]";

fn root() -> PathBuf {
    super::root()
}

/// The text of `path` (relative to the workspace root).
fn text(path: impl AsRef<Path>) -> String {
    let path = root().join(path);
    fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
}

/// The directories under `crates/` that hold a `Cargo.toml`, by name (which is the package
/// name), sorted.
fn crates() -> Vec<String> {
    let dir = root().join("crates");
    let mut names: Vec<String> = fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
        .filter_map(Result::ok)
        .filter(|entry| entry.path().join("Cargo.toml").is_file())
        .map(|entry| entry.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// The method crates: every crate under `crates/` not in [`NOT_METHODS`].
fn method_crates() -> Vec<String> {
    crates()
        .into_iter()
        .filter(|name| !NOT_METHODS.contains(&name.as_str()))
        .collect()
}

/// The `.rs` files under `dir` (relative to the root), recursively, sorted.
fn rust_files(dir: impl AsRef<Path>) -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = fs::read_dir(dir) else {
            return;
        };
        for entry in entries.filter_map(Result::ok) {
            let path = entry.path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }
    let mut files = Vec::new();
    walk(&root().join(dir), &mut files);
    files.sort();
    files
}

/// The lines of `source` that are code: comments and doc comments left out.
fn code_lines(source: &str) -> impl Iterator<Item = (usize, &str)> {
    source
        .lines()
        .enumerate()
        .map(|(k, line)| (k + 1, line))
        .filter(|(_, line)| !line.trim_start().starts_with("//"))
}

/// The `[dependencies]` table of a manifest: its lines up to the next table.
fn dependencies(manifest: &str) -> Vec<&str> {
    manifest
        .lines()
        .skip_while(|line| line.trim() != "[dependencies]")
        .skip(1)
        .take_while(|line| !line.trim_start().starts_with('['))
        .filter(|line| !line.trim().is_empty() && !line.trim_start().starts_with('#'))
        .collect()
}

#[test]
fn the_architecture_doc_is_a_map_of_at_most_200_lines() {
    let lines = text(DOC).lines().count();
    assert!(
        lines <= DOC_MAX_LINES,
        "{DOC} has {lines} lines; a map has at most {DOC_MAX_LINES}: move reference material \
         to the crate docs"
    );
}

#[test]
fn every_crate_the_doc_names_exists_and_every_crate_is_named() {
    let doc = text(DOC);
    let crates = crates();
    // `crates/NAME` in the doc: NAME exists (a placeholder such as `boundary-<method>` is
    // no name).
    for (at, _) in doc.match_indices("crates/") {
        let name: String = doc[at + "crates/".len()..]
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '-' || *c == '_')
            .collect();
        if name.is_empty() || name.ends_with('-') {
            continue;
        }
        assert!(
            crates.contains(&name),
            "{DOC} names crates/{name}, which does not exist"
        );
    }
    // Every crate is named, as `crates/NAME` or `NAME` in backquotes.
    for name in &crates {
        assert!(
            doc.contains(&format!("crates/{name}")) || doc.contains(&format!("`{name}`")),
            "{DOC} does not name the crate {name}: the map shows every crate"
        );
    }
    // And the workspace is exactly those crates and xtask.
    let manifest = text("Cargo.toml");
    for name in &crates {
        assert!(
            manifest.contains(&format!("\"crates/{name}\"")),
            "crates/{name} is not a member of the workspace"
        );
    }
}

#[test]
fn every_invariant_of_the_doc_names_its_tidy_test() {
    let doc = text(DOC);
    let tidy = text("xtask/src/tidy.rs");
    let mut invariants = 0;
    // An invariant is a paragraph opening with `**Invariant:**`.
    for paragraph in doc.split("\n\n").filter(|p| p.starts_with("**Invariant")) {
        invariants += 1;
        let test = paragraph
            .split("tidy: `")
            .nth(1)
            .and_then(|rest| rest.split('`').next())
            .unwrap_or_else(|| panic!("{DOC}: an invariant names no tidy test: {paragraph}"));
        assert!(
            tidy.contains(&format!("fn {test}()")),
            "{DOC} names the tidy test {test}, which xtask/src/tidy.rs lacks"
        );
    }
    assert!(invariants >= 5, "{DOC} states {invariants} invariants");
}

#[test]
fn core_is_the_bottom_layer_and_holds_nothing_method_specific() {
    let manifest = text("crates/boundary-core/Cargo.toml");
    for line in dependencies(&manifest) {
        let name = line.split(['=', '.']).next().unwrap_or_default().trim();
        assert!(
            !name.starts_with("boundary"),
            "boundary-core depends on {name}: the core is the bottom layer"
        );
        assert!(
            name != "num-bigint",
            "boundary-core depends on num-bigint: exact arithmetic is boundary-exact's"
        );
    }
    let methods = method_crates();
    for file in rust_files("crates/boundary-core/src") {
        let source = fs::read_to_string(&file).unwrap_or_default();
        for method in &methods {
            let path = method.replace('-', "_");
            assert!(
                !source.contains(&format!("{path}::")),
                "{} names {path}: the core knows no method",
                file.display()
            );
        }
    }
}

#[test]
fn every_method_crate_is_a_feature_of_the_facade_and_in_its_registry() {
    let methods = method_crates();
    assert!(methods.len() >= 10, "method crates: {methods:?}");
    let manifest = text("crates/boundary/Cargo.toml");
    let default = manifest
        .lines()
        .find(|l| l.trim_start().starts_with("default ="))
        .unwrap_or_default();
    let registry: String = rust_files("crates/boundary/src")
        .iter()
        .map(|f| fs::read_to_string(f).unwrap_or_default())
        .collect();
    for krate in &methods {
        let method = krate.trim_start_matches("boundary-");
        assert!(
            manifest.contains(&format!("{method} = [\"dep:{krate}\"")),
            "crates/boundary/Cargo.toml has no feature {method} for {krate}"
        );
        assert!(
            default.contains(&format!("\"{method}\"")),
            "the facade's default features lack {method}"
        );
        assert!(
            registry.contains(&krate.replace('-', "_")),
            "the facade (crates/boundary/src) never names {krate}: it is not registered"
        );
    }
}

#[test]
fn libraries_print_nothing_and_touch_no_file() {
    let mut libraries: Vec<String> = LIBRARIES.iter().map(|s| (*s).to_owned()).collect();
    libraries.extend(method_crates());
    let patterns = ["std::fs", "fs::", "File::open", "File::create", "read_dir("];
    let prints = [
        "println!(",
        "print!(",
        "dbg!(",
        "std::io::stdout",
        "std::io::stderr",
    ];
    for krate in &libraries {
        let lib = format!("crates/{krate}/src/lib.rs");
        // The facade has the lint too once it opens with it; the text check holds it anyway.
        if krate != "boundary" {
            assert!(
                text(&lib).starts_with(NO_OUTPUT_NO_FILES),
                "{lib} does not open with `{NO_OUTPUT_NO_FILES}`"
            );
        }
        for file in rust_files(format!("crates/{krate}/src")) {
            let source = fs::read_to_string(&file).unwrap_or_default();
            let lines: Vec<&str> = source.lines().collect();
            for (number, line) in code_lines(&source) {
                assert!(
                    !prints.iter().any(|p| line.contains(p)),
                    "{}:{number}: a library crate prints: {}",
                    file.display(),
                    line.trim()
                );
                if !patterns.iter().any(|p| line.contains(p)) {
                    continue;
                }
                let allowed = number >= 2
                    && lines[number - 2].contains("#[allow(clippy::disallowed_methods)]")
                    && FILE_SYSTEM_EXCEPTIONS
                        .iter()
                        .any(|(k, f)| k == krate && file.ends_with(f));
                assert!(
                    allowed,
                    "{}:{number}: a library crate touches the file system: {}",
                    file.display(),
                    line.trim()
                );
            }
        }
    }
}

#[test]
fn the_cli_reads_each_input_once_into_a_frame() {
    let readers = [
        "read_particles(",
        "read_particle_file(",
        "read_positions(",
        "particle_line(",
    ];
    let mut frames = 0;
    for file in rust_files("crates/boundary-cli/src") {
        let source = fs::read_to_string(&file).unwrap_or_default();
        for (number, line) in code_lines(&source) {
            for reader in readers {
                assert!(
                    !line.contains(reader),
                    "{}:{number}: the CLI reads particles with {reader}; read a \
                     boundary_io::Frame once (read_frame) and pass it on",
                    file.display()
                );
            }
            frames += line.matches("read_frame(").count();
        }
    }
    assert!(frames > 0, "the CLI never calls read_frame");
}

#[test]
fn binding_errors_name_no_cli_flag() {
    for krate in ["boundary-py", "boundary-capi"] {
        for file in rust_files(format!("crates/{krate}/src")) {
            let source = fs::read_to_string(&file).unwrap_or_default();
            for (number, line) in code_lines(&source) {
                // The string literals of the line: every other piece between quotes.
                let flag = line.split('"').skip(1).step_by(2).find(|literal| {
                    literal.match_indices("--").any(|(at, _)| {
                        literal[at + 2..].starts_with(|c: char| c.is_ascii_lowercase())
                    })
                });
                assert!(
                    flag.is_none(),
                    "{}:{number}: a binding's text names a CLI flag ({:?}); name the \
                     binding's own argument",
                    file.display(),
                    flag.unwrap_or_default()
                );
            }
        }
    }
}
