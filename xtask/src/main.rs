//! Project tasks, run as `cargo xtask <task>` (alias in `.cargo/config.toml`).
//!
//! - `cargo xtask test`: `cargo fmt --check`, `cargo xtask package`,
//!   `cargo clippy --workspace --all-targets -D warnings`, `cargo xtask doc` and
//!   `cargo test --workspace`. The
//!   workspace includes the MPI driver `crates/boundary-mpi` (outside `default-members`), whose
//!   tests compare `mpirun -np 2` and `-np 4` with the single-process labels; without Open MPI
//!   it is excluded, with a note saying so. What CI runs (`.ci/run`).
//! - `cargo xtask test-mpi`: only the MPI driver's part of `test`.
//! - `cargo xtask test-bindings`: only the bindings' part of `test`: the C and C++ examples of
//!   `examples/c/` (built with the system `cc`/`c++` against `crates/boundary-capi`, run on the
//!   public data, their labels compared with the CLI's), then the Python package
//!   `crates/boundary-py`: its wheel built by maturin into a virtual environment
//!   (`target/py-venv`; numpy, pytest, maturin and mypy installed there with pip when
//!   missing), its pytest suite run from outside the source tree against the installed wheel
//!   and the bundled `fixtures/`, and `examples/python/quickstart.py`. Without a C compiler, or without a
//!   Python >= 3.9 with venv and pip (or with `BOUNDARY_PYTHON=skip`), that part is skipped
//!   with a note saying why, as for MPI.
//! - `cargo xtask sweep [ARGS…]`: run the comparison sweep
//!   (every detector on every scene) in release mode; ARGS go to the sweep (`--help` lists them).
//!   A full run (no argument selecting scenes or methods) also rewrites `BENCHMARKS.md` and the
//!   README's picture `docs/img/vortex2d_t4.png`.
//! - `cargo xtask fixtures`: regenerate the scenes in `fixtures/`.
//! - `cargo xtask prereqs`: only check (and where possible install) the MPI and ParaView
//!   prerequisites.
//! - `cargo xtask package`: `cargo package --workspace --no-verify`: metadata, contents and
//!   dependencies fit for crates.io. Reads the crates.io index (network), builds nothing.
//! - `cargo xtask doc`: `cargo doc --workspace --no-deps` with `RUSTDOCFLAGS=-D warnings`
//!   (a broken intra-doc link fails it), the same packages as clippy.
//! - `cargo xtask check-deps`: the dependency rules of `docs/ARCHITECTURE.md`, from the
//!   dependency graph (`cargo tree`): boundary-core has no file-format, CLI or big-integer
//!   dependency, and no method crate has an IO dependency (direct or not). Also the first step
//!   of `test`.
//! - Tidy tests (`src/tidy.rs`, run by `cargo test -p xtask` and so by `test`): the
//!   invariants of `docs/ARCHITECTURE.md`, checked on the source tree as text.
//!
//! xtask depends on the standard library only, so that it builds on a machine that lacks the
//! prerequisites it installs.
//!
//! # Prerequisites
//! The default members need nothing beyond a Rust toolchain (no system library, no bindgen).
//! The ParaView filter's tests (`crates/boundary-cli/tests/paraview.rs`) need ParaView's
//! `pvpython` (Debian: `paraview python3-paraview`); `cargo xtask test` installs them with
//! `apt-get --no-install-recommends` when it runs as root, and otherwise (or with
//! `BOUNDARY_PARAVIEW=skip`) says so, while each of those tests prints `SKIPPED` and passes.
//! The MPI driver needs Open MPI and libclang (Debian: `libopenmpi-dev openmpi-bin
//! libclang-dev`: `mpicc` and libclang for the `mpi` crate's build, which runs bindgen,
//! `mpirun` for its tests). `cargo xtask test` installs them with `apt-get` when it runs as
//! root (CI, containers); when it cannot, or when `BOUNDARY_MPI=skip` is set, it says that
//! the MPI checks were skipped and why, prints the command that installs them, and still
//! succeeds: the rest of the workspace never needs MPI nor libclang.

use std::env;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

#[cfg(test)]
mod tidy;

fn main() -> ExitCode {
    let args: Vec<String> = env::args().skip(1).collect();
    let (task, rest) = match args.split_first() {
        Some((task, rest)) => (task.as_str(), rest),
        None => ("help", &[][..]),
    };
    let result = match task {
        "test" => test(rest),
        "test-mpi" => test_mpi(),
        "test-bindings" => test_bindings(),
        "sweep" => sweep(rest),
        "fixtures" => fixtures(rest),
        "check-deps" => check_deps(),
        "package" => package(),
        "doc" => {
            python_extension_env();
            // The MPI driver when Open MPI is already there (this task installs nothing).
            let mpi = !env::var("BOUNDARY_MPI").is_ok_and(|v| v == "skip")
                && has_program("mpicc")
                && libclang_found();
            doc(&workspace_exclusions(mpi, python_usable().is_some()))
        }
        "train-svm" => train_svm(rest),
        "prereqs" => {
            if let Err(why) = mpi_prereqs() {
                eprintln!("xtask: MPI driver not buildable here: {why}");
            }
            if let Err(why) = paraview_prereqs() {
                eprintln!("xtask: ParaView filter not testable here: {why}");
            }
            Ok(())
        }
        "help" | "--help" | "-h" => {
            println!("{}", usage());
            Ok(())
        }
        other => Err(format!("unknown task '{other}'\n{}", usage())),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("xtask: error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn usage() -> &'static str {
    "usage: cargo xtask <task>\n\
     tasks:\n  \
     test       rustfmt --check, clippy -D warnings, the whole test suite; the\n             \
     MPI driver included when Open MPI is installed or installable (CI)\n  \
     test-mpi   only the MPI driver's part of `test`\n  \
     test-bindings  only the C examples and the Python package's part of `test`\n  \
     sweep      every detector on every scene: target/sweep/report.md; a full run also\n             \
BENCHMARKS.md and its pictures in docs/img (--scale adds the scale tier)\n  \
     fixtures   regenerate the generated scenes in fixtures/\n  \
     train-svm  retrain the shipped svm models (seeded) and score them on held-out scenes:\n             \
crates/boundary-svm/models/, target/svm/training.md\n  \
     prereqs    check the MPI and ParaView prerequisites (install them when root with apt-get)\n  \
     check-deps boundary-core has no format/CLI/big-integer dependency, method crates no IO dependency\n  \
     package    `cargo package --workspace --no-verify` (metadata, contents, dependencies)\n  \
     doc        the API documentation, every rustdoc warning an error"
}

/// The workspace root (the parent of this crate's directory).
fn root() -> PathBuf {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    manifest.parent().unwrap_or(manifest).to_path_buf()
}

/// Runs `cargo ARGS` in the workspace root, echoing the command; an error if it fails.
fn cargo(args: &[&str]) -> Result<(), String> {
    cargo_with_env(args, &[])
}

/// [`cargo`] with extra environment variables for that command only.
fn cargo_with_env(args: &[&str], envs: &[(&str, String)]) -> Result<(), String> {
    let cargo = env::var("CARGO").unwrap_or_else(|_| "cargo".to_owned());
    let shown: Vec<String> = envs.iter().map(|(k, v)| format!("{k}={v:?} ")).collect();
    eprintln!("xtask: {}cargo {}", shown.concat(), args.join(" "));
    let status = Command::new(&cargo)
        .args(args)
        .envs(envs.iter().map(|(k, v)| (k, v)))
        .current_dir(root())
        .status()
        .map_err(|e| format!("cannot run {cargo}: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("`cargo {}` failed ({status})", args.join(" ")))
    }
}

/// The MPI driver's package: a workspace member outside `default-members`.
const MPI_PACKAGE: &str = "boundary-mpi";

/// Whether the MPI driver can be built here; says why not when it cannot.
fn mpi_usable() -> bool {
    match mpi_prereqs() {
        Ok(()) => true,
        Err(why) => {
            eprintln!(
                "xtask: NOTE: MPI checks SKIPPED ({MPI_PACKAGE}: clippy, tests including the \
                 mpirun equality tests): {why}"
            );
            false
        }
    }
}

/// fmt, clippy and the tests of the whole workspace; the MPI driver only when `mpi`, the
/// Python package only when `python` (its build script needs a Python interpreter).
fn test_workspace(mpi: bool, python: bool, rest: &[String]) -> Result<(), String> {
    let exclude = workspace_exclusions(mpi, python);
    check_deps()?;
    cargo(&["fmt", "--all", "--", "--check"])?;
    package()?;
    let mut args = vec!["clippy", "--workspace"];
    args.extend(&exclude);
    args.extend(["--all-targets", "--", "-D", "warnings"]);
    cargo(&args)?;
    doc(&exclude)?;
    let mut args = vec!["test", "--workspace"];
    args.extend(&exclude);
    args.extend(rest.iter().map(String::as_str));
    cargo(&args)
}

fn test(rest: &[String]) -> Result<(), String> {
    python_extension_env();
    let mpi = mpi_usable();
    if let Err(why) = paraview_prereqs() {
        eprintln!(
            "xtask: NOTE: ParaView checks SKIPPED (boundary-cli's tests/paraview.rs prints \
             SKIPPED for each): {why}"
        );
    }
    let python = python_usable();
    test_workspace(mpi, python.is_some(), rest)?;
    let cli = bindings_build(&workspace_exclusions(mpi, python.is_some()))?;
    c_examples(&cli)?;
    match python {
        Some(python) => python_package(&python),
        None => Ok(()),
    }
}

/// clippy and the tests of the MPI driver alone (`cargo xtask test-mpi`).
fn test_mpi() -> Result<(), String> {
    if !mpi_usable() {
        return Ok(());
    }
    cargo(&[
        "clippy",
        "-p",
        MPI_PACKAGE,
        "--all-targets",
        "--",
        "-D",
        "warnings",
    ])?;
    cargo(&["test", "-p", MPI_PACKAGE])
}

/// Makes sure `mpicc` and `mpirun` exist: installs Open MPI with apt-get when root, else says
/// why not (with the command to run).
fn mpi_prereqs() -> Result<(), String> {
    if env::var("BOUNDARY_MPI").is_ok_and(|v| v == "skip") {
        return Err("BOUNDARY_MPI=skip is set".to_owned());
    }
    // The `mpi` crate's build runs bindgen, which needs libclang.
    let found = || has_program("mpicc") && has_program("mpirun") && libclang_found();
    if found() {
        return Ok(());
    }
    let packages = ["libopenmpi-dev", "openmpi-bin", "libclang-dev"];
    let install = format!("sudo apt-get install -y {}", packages.join(" "));
    if !(is_root() && has_program("apt-get")) {
        return Err(format!(
            "Open MPI (mpicc, mpirun) or libclang (bindgen, for the mpi crate) not found and \
             not root with apt-get to install them; \
             install them with:\n    {install}"
        ));
    }
    eprintln!("xtask: Open MPI or libclang not found (needed by {MPI_PACKAGE}); installing them");
    run_system("apt-get", &["update", "-qq"])?;
    let mut args = vec!["install", "-y", "-qq"];
    args.extend(packages);
    run_system("apt-get", &args)?;
    if found() {
        Ok(())
    } else {
        Err(format!(
            "installed {} but mpicc or mpirun is still not on PATH",
            packages.join(" ")
        ))
    }
}

/// The Debian packages of ParaView's `pvpython`, without their recommendations (the MPI
/// launcher and the documentation, which the ParaView tests do not use).
const PARAVIEW_PACKAGES: [&str; 2] = ["paraview", "python3-paraview"];

/// Makes sure ParaView's `pvpython` exists for the ParaView filter's tests: installs it with
/// apt-get when root, else says why not (with the command to run).
fn paraview_prereqs() -> Result<(), String> {
    if env::var("BOUNDARY_PARAVIEW").is_ok_and(|v| v == "skip") {
        return Err("BOUNDARY_PARAVIEW=skip is set".to_owned());
    }
    if has_program("pvpython") {
        return Ok(());
    }
    let install = format!(
        "sudo apt-get install -y --no-install-recommends {}",
        PARAVIEW_PACKAGES.join(" ")
    );
    if !(is_root() && has_program("apt-get")) {
        return Err(format!(
            "ParaView's pvpython not found and not root with apt-get to install it; install \
             it with:\n    {install}"
        ));
    }
    eprintln!("xtask: ParaView's pvpython not found (needed by the ParaView filter's tests); installing it");
    run_system("apt-get", &["update", "-qq"])?;
    let mut args = vec!["install", "-y", "-qq", "--no-install-recommends"];
    args.extend(PARAVIEW_PACKAGES);
    run_system("apt-get", &args)?;
    if has_program("pvpython") {
        Ok(())
    } else {
        Err(format!(
            "installed {} but pvpython is still not on PATH",
            PARAVIEW_PACKAGES.join(" ")
        ))
    }
}

/// The sweep in release mode. A full run (no argument that narrows it or moves its inputs)
/// also rewrites `BENCHMARKS.md` with its speed-against-error pictures
/// (`docs/img/speed_vs_error_{2d,3d}.png`) and the README's picture
/// `docs/img/vortex2d_t4.png`, so that they are always the output of the documented command;
/// a narrowed run leaves them alone.
fn sweep(rest: &[String]) -> Result<(), String> {
    let root = root();
    let benchmarks = root.join("BENCHMARKS.md").display().to_string();
    let pictures = root.join("docs/img").display().to_string();
    let picture = root.join("docs/img/vortex2d_t4.png").display().to_string();
    let mut args = vec!["run", "--release", "--quiet", "-p", "boundary-sweep", "--"];
    args.extend(rest.iter().map(String::as_str));
    if writes_pages(rest) {
        args.extend([
            "--benchmarks",
            &benchmarks,
            "--benchmark-pictures",
            &pictures,
            "--frame-picture",
            &picture,
        ]);
    } else {
        eprintln!("xtask: a narrowed sweep: BENCHMARKS.md and docs/img are left as they are");
    }
    cargo(&args)
}

/// Whether a sweep with arguments `rest` is a full run, whose summary may replace the
/// committed `BENCHMARKS.md`: none of the arguments selects scenes or methods, shortens the
/// run, reads other inputs, or already names the pages.
fn writes_pages(rest: &[String]) -> bool {
    const NARROWING: [&str; 10] = [
        "--scenes",
        "--methods",
        "--quick",
        "--no-single-thread",
        "--manifest",
        "--data-dir",
        "--benchmarks",
        "--benchmark-pictures",
        "--frame-picture",
        "--help",
    ];
    !rest.iter().any(|arg| {
        arg == "-h"
            || NARROWING
                .iter()
                .any(|n| arg == n || arg.starts_with(&format!("{n}=")))
    })
}

fn fixtures(rest: &[String]) -> Result<(), String> {
    let mut args = vec![
        "run",
        "--release",
        "--quiet",
        "-p",
        "boundary-scenes",
        "--bin",
        "make-fixtures",
        "--",
    ];
    args.extend(rest.iter().map(String::as_str));
    cargo(&args)
}

/// Retrains the shipped `svm` models (deterministic: seeded sampling, linfa-svm's SMO) and
/// writes the held-out confusion matrices to `target/svm/training.md`.
fn train_svm(rest: &[String]) -> Result<(), String> {
    let mut args = vec![
        "run",
        "--release",
        "--quiet",
        "-p",
        "boundary-svm-train",
        "--bin",
        "train-svm",
        "--",
    ];
    args.extend(rest.iter().map(String::as_str));
    cargo(&args)
}

/// Whether libclang is where bindgen (clang-sys) looks for it.
fn libclang_found() -> bool {
    // `libclang.so*` or `libclang-14.so*`, but not `libclang-cpp.so*` (the C++ library,
    // installed without libclang by some LLVM packages; bindgen cannot use it).
    let is_libclang = |name: &str| {
        name.starts_with("libclang") && name.contains(".so") && !name.starts_with("libclang-cpp")
    };
    let has_libclang = |dir: &Path| -> bool {
        std::fs::read_dir(dir)
            .map(|entries| {
                entries
                    .flatten()
                    .any(|e| is_libclang(&e.file_name().to_string_lossy()))
            })
            .unwrap_or(false)
    };
    if let Ok(dir) = env::var("LIBCLANG_PATH") {
        if has_libclang(Path::new(&dir)) {
            return true;
        }
    }
    let mut dirs: Vec<PathBuf> = [
        "/usr/lib",
        "/usr/lib64",
        "/usr/local/lib",
        "/usr/lib/x86_64-linux-gnu",
        "/usr/lib/aarch64-linux-gnu",
    ]
    .iter()
    .map(PathBuf::from)
    .collect();
    // Debian and Ubuntu keep it under /usr/lib/llvm-N/lib.
    if let Ok(entries) = std::fs::read_dir("/usr/lib") {
        for entry in entries.flatten() {
            if entry.file_name().to_string_lossy().starts_with("llvm") {
                dirs.push(entry.path().join("lib"));
            }
        }
    }
    dirs.iter().any(|d| has_libclang(d))
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
        .unwrap_or(false)
}

fn has_program(name: &str) -> bool {
    env::var_os("PATH")
        .map(|paths| env::split_paths(&paths).any(|dir| dir.join(name).is_file()))
        .unwrap_or(false)
}

fn run_system(program: &str, args: &[&str]) -> Result<(), String> {
    eprintln!("xtask: {program} {}", args.join(" "));
    let status = Command::new(program)
        .args(args)
        .env("DEBIAN_FRONTEND", "noninteractive")
        .status()
        .map_err(|e| format!("cannot run {program}: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("`{program} {}` failed ({status})", args.join(" ")))
    }
}

/// The method crates (and the toolboxes they share): no file, no output, no IO dependency.
const METHOD_CRATES: &[&str] = &[
    "boundary-exact",
    "boundary-dilts",
    "boundary-ia",
    "boundary-ge",
    "boundary-sph",
    "boundary-marrone",
    "boundary-muller",
    "boundary-divr",
    "boundary-asymmetry",
    "boundary-randles",
    "boundary-lnm",
    "boundary-hpr",
    "boundary-svm",
    "boundary-resample",
];

/// IO dependencies: our file and CLI crates, file-format readers and writers, compression,
/// command-line parsing and terminal output, temporary files, plotting. A method crate must
/// not depend on any of them, directly or through another crate.
const IO_DEPENDENCIES: &[&str] = &[
    "boundary-io",
    "boundary-cli",
    "boundary-scenes",
    "boundary-sweep",
    "boundary-mpi",
    "vtkio",
    "ply-rs-bw",
    "quick-xml",
    "base64",
    "flate2",
    "tobj",
    "csv",
    "toml",
    "clap",
    "indicatif",
    "glob",
    "tempfile",
    "plotters",
    "mpi",
];

/// Besides the IO dependencies, boundary-core knows no serialisation format: it holds the
/// types every crate shares, and a format belongs to boundary-io (`svm` may read its JSON
/// model; the core may not).
const FORMAT_DEPENDENCIES: &[&str] = &["serde", "serde_json"];

/// Nor does boundary-core hold a method's arithmetic: the exact covering predicate, with its
/// arbitrary-precision integers, is `boundary-exact`'s.
const METHOD_ARITHMETIC: &[&str] = &["num-bigint"];

/// The rules: each crate with the dependencies it must not have.
fn dependency_rules() -> Vec<(&'static str, Vec<&'static str>)> {
    let core: Vec<&str> = IO_DEPENDENCIES
        .iter()
        .chain(FORMAT_DEPENDENCIES)
        .chain(METHOD_ARITHMETIC)
        .copied()
        .collect();
    let mut rules = vec![("boundary-core", core)];
    for &krate in METHOD_CRATES {
        rules.push((krate, IO_DEPENDENCIES.to_vec()));
    }
    rules
}

/// The names of the packages in the output of
/// `cargo tree -p CRATE -e normal --prefix none --format {p}` (one `name vX.Y.Z [(path)] [(*)]`
/// per line; the first line is the crate itself, which is not its own dependency).
fn tree_packages(tree: &str) -> Vec<&str> {
    tree.lines()
        .skip(1)
        .filter_map(|line| line.split_whitespace().next())
        .collect()
}

/// The rule violations of `krate` whose normal dependency tree (as [`tree_packages`] reads it)
/// is `tree`: one message per forbidden package found.
fn forbidden_dependencies(krate: &str, tree: &str, forbidden: &[&str]) -> Vec<String> {
    let mut found: Vec<&str> = tree_packages(tree)
        .into_iter()
        .filter(|name| forbidden.contains(name))
        .collect();
    found.sort_unstable();
    found.dedup();
    found
        .into_iter()
        .map(|dep| {
            format!("{krate} depends on {dep} (see `cargo tree -p {krate} -e normal -i {dep}`)")
        })
        .collect()
}

/// `cargo xtask check-deps`: every rule of [`dependency_rules`] on the real dependency graph.
fn check_deps() -> Result<(), String> {
    let cargo = env::var("CARGO").unwrap_or_else(|_| "cargo".to_owned());
    let mut problems = Vec::new();
    for (krate, forbidden) in dependency_rules() {
        let output = Command::new(&cargo)
            .args([
                "tree", "--quiet", "-p", krate, "-e", "normal", "--prefix", "none",
            ])
            .args(["--format", "{p}"])
            .current_dir(root())
            .output()
            .map_err(|e| format!("cannot run {cargo}: {e}"))?;
        if !output.status.success() {
            return Err(format!(
                "`cargo tree -p {krate}` failed: {}",
                String::from_utf8_lossy(&output.stderr).trim()
            ));
        }
        let tree = String::from_utf8_lossy(&output.stdout);
        if tree_packages(&tree).is_empty() && !tree.starts_with(krate) {
            return Err(format!("`cargo tree -p {krate}` printed no tree"));
        }
        problems.extend(forbidden_dependencies(krate, &tree, &forbidden));
    }
    if problems.is_empty() {
        eprintln!(
            "xtask: check-deps: boundary-core and {} method crates hold the dependency rules",
            METHOD_CRATES.len()
        );
        Ok(())
    } else {
        Err(format!(
            "dependency rules broken (docs/ARCHITECTURE.md):\n  {}",
            problems.join("\n  ")
        ))
    }
}

/// `cargo package --workspace --no-verify`: every member's metadata, contents and
/// dependencies are fit for a registry (a published crate may not depend on an unpublished
/// one; dev-dependencies on the test scenes are path only, which cargo drops from the
/// package). Reads the crates.io index; builds nothing. `--allow-dirty`: a work in progress
/// packages too (CI runs on a clean checkout, where it changes nothing).
fn package() -> Result<(), String> {
    cargo(&["package", "--workspace", "--no-verify", "--allow-dirty"])
}

/// The API documentation of the workspace (without the exclusions `exclude`, as for clippy)
/// with every rustdoc warning an error: a broken or private intra-doc link, an unclosed HTML
/// tag, a bare URL. `RUSTDOCFLAGS` of the environment is kept, `-D warnings` added to it.
fn doc(exclude: &[&str]) -> Result<(), String> {
    let flags = match env::var("RUSTDOCFLAGS") {
        Ok(flags) if !flags.trim().is_empty() => format!("{flags} -D warnings"),
        _ => "-D warnings".to_owned(),
    };
    let mut args = vec!["doc", "--workspace", "--no-deps"];
    args.extend(exclude);
    cargo_with_env(&args, &[("RUSTDOCFLAGS", flags)])
}

/// The Python package's crate: a workspace member outside `default-members`.
const PY_PACKAGE: &str = "boundary-py";

/// Where `cargo xtask test` keeps the Python virtual environment, wheels and outputs.
const PY_VENV: &str = "target/py-venv";

/// The bindings' part of `test` alone (`cargo xtask test-bindings`).
fn test_bindings() -> Result<(), String> {
    python_extension_env();
    let python = python_usable();
    // The test run's package selection, without installing anything.
    let mpi = !env::var("BOUNDARY_MPI").is_ok_and(|v| v == "skip")
        && has_program("mpicc")
        && has_program("mpirun");
    let cli = bindings_build(&workspace_exclusions(mpi, python.is_some()))?;
    c_examples(&cli)?;
    match python {
        Some(python) => python_package(&python),
        None => Ok(()),
    }
}

/// Builds `boundary-py` as an extension module in every cargo command of this process (as
/// maturin does): its cdylib then leaves the Python symbols to the interpreter instead of
/// linking libpython, which a machine may lack (Debian ships it in python3-dev). The same
/// value for clippy, test and the build keeps pyo3's build script from rerunning.
fn python_extension_env() {
    env::set_var("PYO3_BUILD_EXTENSION_MODULE", "1");
}

/// The `--exclude` arguments of the workspace commands: the MPI driver unless `mpi`, the
/// Python package unless `python`.
fn workspace_exclusions(mpi: bool, python: bool) -> Vec<&'static str> {
    let mut exclude = Vec::new();
    if !mpi {
        exclude.extend(["--exclude", MPI_PACKAGE]);
    }
    if !python {
        exclude.extend(["--exclude", PY_PACKAGE]);
    }
    exclude
}

/// Puts the CLI (the reference labels) and the C API's libraries into `target/debug`; returns
/// the CLI's path. The same packages, targets (those `cargo test` builds) and profile as the
/// test run, so that cargo finds its units fresh: only the C API's cdylib/staticlib are new.
fn bindings_build(exclude: &[&str]) -> Result<PathBuf, String> {
    let mut args = vec!["build", "--profile", "test", "--workspace"];
    args.extend(exclude);
    args.extend(["--lib", "--bins", "--tests", "--examples"]);
    cargo(&args)?;
    Ok(root().join("target/debug/boundary"))
}

/// A Python >= 3.9 interpreter to build the package with, or `None` with a note saying why
/// the Python checks are skipped.
fn python_usable() -> Option<String> {
    let skip = |why: &str| {
        eprintln!(
            "xtask: NOTE: Python checks SKIPPED ({PY_PACKAGE}: clippy, wheel, pytest, \
             examples/python): {why}"
        );
        None
    };
    if env::var("BOUNDARY_PYTHON").is_ok_and(|v| v == "skip") {
        return skip("BOUNDARY_PYTHON=skip is set");
    }
    let python = env::var("PYO3_PYTHON").unwrap_or_else(|_| "python3".to_owned());
    let version = Command::new(&python)
        .args([
            "-c",
            "import sys; assert sys.version_info >= (3, 9), sys.version; import venv, ensurepip",
        ])
        .output();
    match version {
        Ok(out) if out.status.success() => Some(python),
        Ok(out) => skip(&format!(
            "{python} is older than 3.9 or lacks venv/ensurepip (Debian: apt-get install \
             python3-venv): {}",
            String::from_utf8_lossy(&out.stderr).trim()
        )),
        Err(e) => skip(&format!(
            "no Python interpreter ({python}: {e}); install Python >= 3.9 with venv"
        )),
    }
}

/// Runs `program args` in the workspace root with extra environment `envs`, echoing it.
fn run_in_root(program: &Path, args: &[&str], envs: &[(&str, &Path)]) -> Result<(), String> {
    run_in(&root(), program, args, envs)
}

/// Runs `program args` in the folder `dir` with extra environment `envs`, echoing it.
fn run_in(dir: &Path, program: &Path, args: &[&str], envs: &[(&str, &Path)]) -> Result<(), String> {
    eprintln!(
        "xtask: (in {}) {} {}",
        dir.display(),
        program.display(),
        args.join(" ")
    );
    let mut command = Command::new(program);
    command.args(args).current_dir(dir);
    for (key, value) in envs {
        command.env(key, value);
    }
    let status = command
        .status()
        .map_err(|e| format!("cannot run {}: {e}", program.display()))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!(
            "`{} {}` failed ({status})",
            program.display(),
            args.join(" ")
        ))
    }
}

/// The C and C++ examples of `examples/c/`, built against the C API's static library with the
/// system compilers and run on public scenes (and the C one on a generated scene with a radius
/// per particle): each compares its labels with the CLI's.
fn c_examples(cli: &Path) -> Result<(), String> {
    let (Some(cc), Some(cxx)) = (
        compiler(&["cc", "gcc", "clang"]),
        compiler(&["c++", "g++", "clang++"]),
    ) else {
        eprintln!(
            "xtask: NOTE: C/C++ examples SKIPPED: no C and C++ compiler (cc, c++) on PATH \
             (Debian: apt-get install build-essential)"
        );
        return Ok(());
    };
    let root = root();
    let out = root.join("target/capi-examples");
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let library = root.join("target/debug/libboundary_capi.a");
    let include = root.join("crates/boundary-capi/include");
    let link = ["-lpthread", "-ldl", "-lm"];
    let c_exe = out.join("detect_c");
    let cxx_exe = out.join("detect_cpp");
    let builds: [(&str, &str, &str, &Path); 2] = [
        (&cc, "-std=c99", "examples/c/detect.c", &c_exe),
        (&cxx, "-std=c++17", "examples/c/detect.cpp", &cxx_exe),
    ];
    for (compiler, std, source, exe) in builds {
        let include_flag = format!("-I{}", include.display());
        let mut args = vec![
            std,
            "-O2",
            "-Wall",
            "-Wextra",
            "-Werror",
            source,
            include_flag.as_str(),
        ];
        let library = library.to_string_lossy();
        let exe_text = exe.to_string_lossy();
        args.push(&library);
        args.extend(link);
        args.extend(["-o", &exe_text]);
        run_in_root(Path::new(compiler), &args, &[])?;
    }
    let data = data_dir();
    // (example, scene file, r, method, params): 2D and 3D, a parameter, a method with margin
    // and one without.
    let cases: [(&Path, &str, &str, &str, &str); 4] = [
        (
            &c_exe,
            "particles2d/sandim_vortex_spin_frame_050_1698.csv",
            "0.022105",
            "exact",
            "",
        ),
        (
            &c_exe,
            "particles3d/dualsphysics_dambreak3d_dp0.02_fluid.csv",
            "0.0346",
            "ge",
            "depth=3",
        ),
        (
            &cxx_exe,
            "particles3d/dualsphysics_dambreak3d_dp0.02_fluid.csv",
            "0.0346",
            "exact",
            "",
        ),
        (
            &cxx_exe,
            "particles2d/dualsphysics_dambreak2d_dp0.02_fluid_4416.csv",
            "0.0283",
            "muller",
            "threshold=0.3",
        ),
    ];
    for (k, (exe, file, r, method, params)) in cases.iter().enumerate() {
        let labels = out.join(format!("labels{k}.csv"));
        let input = data.join(file);
        let (input, labels_text) = (input.to_string_lossy(), labels.to_string_lossy());
        let mut args = vec!["detect", &input, "--radius", r, "--method", method];
        if !params.is_empty() {
            args.extend(["--set", params]);
        }
        args.extend(["--output", &labels_text]);
        run_in_root(cli, &args, &[])?;
        run_in_root(exe, &[&labels_text, r, method, params], &[])?;
    }
    // A radius per particle: the C example reads the `radius` column the CLI writes back. A
    // 20 x 20 lattice whose right half has radius factor 0.8, at scale 0.9.
    let graded = out.join("graded.csv");
    let mut text = String::from("x,y,radius\n");
    for k in 0..400 {
        let factor = if k / 20 < 10 { 1.0 } else { 0.8 };
        text.push_str(&format!("{},{},{factor}\n", k / 20, k % 20));
    }
    std::fs::write(&graded, text).map_err(|e| format!("cannot write {}: {e}", graded.display()))?;
    let labels = out.join("labels_radii.csv");
    let (graded_text, labels_text) = (graded.to_string_lossy(), labels.to_string_lossy());
    run_in_root(
        cli,
        &[
            "detect",
            &graded_text,
            "--radius-attribute",
            "radius",
            "--radius-scale",
            "0.9",
            "--output",
            &labels_text,
        ],
        &[],
    )?;
    run_in_root(&c_exe, &[&labels_text, "0.9", "exact", ""], &[])?;
    Ok(())
}

/// The first of `names` found on PATH.
fn compiler(names: &[&str]) -> Option<String> {
    names
        .iter()
        .find(|n| has_program(n))
        .map(|n| (*n).to_owned())
}

/// The public data directory (`BOUNDARY_DATA_DIR`, else `../shared/data`).
fn data_dir() -> PathBuf {
    env::var_os("BOUNDARY_DATA_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join("../shared/data"))
}

/// Builds the Python package's wheel (maturin, profile `wheel`: the test profile's
/// optimisation without debug info, in the workspace's target dir) in
/// the virtual environment `target/py-venv`, installs it there and runs its pytest suite
/// (from `target/py-venv`, outside the source tree, so that the installed wheel is what is
/// imported; mypy for its stub and type checks) and `examples/python/quickstart.py`. A
/// missing venv or pip skips it with a note.
fn python_package(python: &str) -> Result<(), String> {
    let root = root();
    let venv = root.join(PY_VENV);
    let venv_python = venv.join("bin/python");
    if !venv_python.is_file() {
        let created = Command::new(python)
            .args(["-m", "venv"])
            .arg(&venv)
            .status()
            .is_ok_and(|s| s.success());
        if !created {
            eprintln!(
                "xtask: NOTE: Python checks SKIPPED: `{python} -m venv {PY_VENV}` failed \
                 (Debian: apt-get install python3-venv)"
            );
            return Ok(());
        }
    }
    let missing: Vec<&str> = ["numpy", "pytest", "maturin", "mypy"]
        .into_iter()
        .filter(|module| {
            !Command::new(&venv_python)
                .args(["-c", &format!("import {module}")])
                .status()
                .is_ok_and(|s| s.success())
        })
        .collect();
    if !missing.is_empty() {
        let mut args = vec!["-m", "pip", "install", "--quiet"];
        args.extend(&missing);
        if let Err(why) = run_in_root(&venv_python, &args, &[]) {
            eprintln!(
                "xtask: NOTE: Python checks SKIPPED: cannot install {} into {PY_VENV} with \
                 pip: {why}",
                missing.join(", ")
            );
            return Ok(());
        }
    }
    let wheels = root.join("target/py-wheels");
    // Only this build's wheel in the directory, so that the one installed is this one.
    let _ = std::fs::remove_dir_all(&wheels);
    let wheels_text = wheels.to_string_lossy();
    let python_text = venv_python.to_string_lossy();
    run_in_root(
        &venv.join("bin/maturin"),
        &[
            "build",
            "--profile",
            "wheel",
            "--manifest-path",
            "crates/boundary-py/Cargo.toml",
            "--interpreter",
            &python_text,
            "--out",
            &wheels_text,
        ],
        &[],
    )?;
    let wheel = std::fs::read_dir(&wheels)
        .map_err(|e| format!("cannot list {}: {e}", wheels.display()))?
        .flatten()
        .map(|e| e.path())
        .find(|p| p.extension().is_some_and(|e| e == "whl"))
        .ok_or_else(|| format!("maturin wrote no wheel into {}", wheels.display()))?;
    let wheel_text = wheel.to_string_lossy();
    run_in_root(
        &venv_python,
        &[
            "-m",
            "pip",
            "install",
            "--quiet",
            "--force-reinstall",
            "--no-deps",
            &wheel_text,
        ],
        &[],
    )?;
    let tests = root.join("crates/boundary-py/tests");
    run_in(
        &venv,
        &venv_python,
        &[
            "-m",
            "pytest",
            "-q",
            // The reasons of skipped tests (an optional solver that is not installed, and the
            // command that installs it).
            "-rs",
            "-p",
            "no:cacheprovider",
            &tests.to_string_lossy(),
        ],
        &[],
    )?;
    let plot = root.join("target/py-quickstart.png");
    let plot_text = plot.to_string_lossy();
    run_in_root(
        &venv_python,
        &["examples/python/quickstart.py", "--plot", &plot_text],
        &[],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What `cargo tree -p boundary-marrone -e normal --prefix none --format {p}` prints,
    /// trimmed, with an IO dependency added through the toolbox.
    const MARRONE_WITH_GLOB: &str = "\
boundary-marrone v0.1.0 (/w/crates/boundary-marrone)
boundary-core v0.1.0 (/w/crates/boundary-core)
nalgebra v0.35.0
rayon v1.12.0
boundary-sph v0.1.0 (/w/crates/boundary-sph)
boundary-core v0.1.0 (/w/crates/boundary-core) (*)
glob v0.3.4
rayon v1.12.0 (*)
";

    #[test]
    fn a_method_crate_with_an_io_dependency_anywhere_in_its_tree_is_reported() {
        let problems =
            forbidden_dependencies("boundary-marrone", MARRONE_WITH_GLOB, IO_DEPENDENCIES);
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert!(
            problems[0].starts_with("boundary-marrone depends on glob"),
            "{problems:?}"
        );
        let clean = MARRONE_WITH_GLOB.replace("glob v0.3.4\n", "");
        assert!(forbidden_dependencies("boundary-marrone", &clean, IO_DEPENDENCIES).is_empty());
    }

    #[test]
    fn the_core_may_not_have_a_format_dependency_that_svm_may_have() {
        let tree = "boundary-core v0.1.0 (/w)\nserde_json v1.0.0\nserde v1.0.0\nryu v1.0.0\n";
        let rules = dependency_rules();
        let core = &rules.iter().find(|(k, _)| *k == "boundary-core").unwrap().1;
        let svm = &rules.iter().find(|(k, _)| *k == "boundary-svm").unwrap().1;
        assert_eq!(
            forbidden_dependencies("boundary-core", tree, core),
            [
                "boundary-core depends on serde (see `cargo tree -p boundary-core -e normal -i serde`)",
                "boundary-core depends on serde_json (see `cargo tree -p boundary-core -e normal -i serde_json`)",
            ]
        );
        assert!(forbidden_dependencies("boundary-svm", tree, svm).is_empty());
    }

    #[test]
    fn the_core_may_not_have_the_big_integers_that_exact_has() {
        let tree = "boundary-core v0.1.0 (/w)\nnum-bigint v0.4.6\nnum-integer v0.1.46\n";
        let rules = dependency_rules();
        let core = &rules.iter().find(|(k, _)| *k == "boundary-core").unwrap().1;
        let exact = &rules
            .iter()
            .find(|(k, _)| *k == "boundary-exact")
            .unwrap()
            .1;
        assert_eq!(
            forbidden_dependencies("boundary-core", tree, core),
            ["boundary-core depends on num-bigint (see `cargo tree -p boundary-core -e normal -i num-bigint`)"]
        );
        assert!(forbidden_dependencies("boundary-exact", tree, exact).is_empty());
    }

    #[test]
    fn the_crate_itself_and_deduplicated_lines_are_read_right() {
        // The first line is the crate itself: boundary-io is not its own IO dependency, and a
        // repeated `(*)` line is one package.
        let tree = "boundary-io v0.1.0 (/w)\nflate2 v1.1.0\nflate2 v1.1.0 (*)\n";
        assert_eq!(tree_packages(tree), ["flate2", "flate2"]);
        assert_eq!(
            forbidden_dependencies("boundary-io", tree, &["boundary-io"]),
            Vec::<String>::new()
        );
        assert_eq!(forbidden_dependencies("x", tree, &["flate2"]).len(), 1);
        assert!(tree_packages("").is_empty());
    }

    #[test]
    fn only_a_full_sweep_rewrites_the_committed_pages() {
        let args = |a: &[&str]| a.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        assert!(writes_pages(&args(&[])));
        assert!(writes_pages(&args(&["--scale", "--threads", "2"])));
        assert!(writes_pages(&args(&["--out", "elsewhere"])));
        assert!(!writes_pages(&args(&["--scenes", "vortex"])));
        assert!(!writes_pages(&args(&["--methods=ia,exact"])));
        assert!(!writes_pages(&args(&["--quick"])));
        assert!(!writes_pages(&args(&["--data-dir", "/data"])));
        assert!(!writes_pages(&args(&["-h"])));
        // A value that only starts like a flag is not one.
        assert!(writes_pages(&args(&["--out", "--quickly"])));
    }

    #[test]
    fn every_method_crate_and_the_core_have_a_rule() {
        let rules = dependency_rules();
        assert_eq!(rules.len(), METHOD_CRATES.len() + 1);
        for (krate, forbidden) in &rules {
            assert!(forbidden.contains(&"boundary-io"), "{krate}");
            assert!(!forbidden.contains(krate), "{krate}");
        }
    }
}
