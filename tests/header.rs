//! The checked-in header `include/dcol.h` must equal the one cbindgen generates from `src/ffi`
//! (build.rs writes it to `$OUT_DIR/dcol.h`), and its version macros must match Cargo.toml.
//!
//! After changing the C API, regenerate the checked-in copy with
//!
//! ```sh
//! DCOL_BLESS=1 cargo test --test header
//! ```

use std::path::PathBuf;

const REGEN: &str = "DCOL_BLESS=1 cargo test --test header";

fn checked_in_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("include/dcol.h")
}

fn generated() -> String {
    let path = env!("DCOL_GENERATED_HEADER");
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("generated header {path}: {e}"))
}

#[test]
fn checked_in_header_is_up_to_date() {
    let generated = generated();
    let path = checked_in_path();
    if std::env::var_os("DCOL_BLESS").is_some() {
        std::fs::write(&path, &generated).expect("write include/dcol.h");
        eprintln!("wrote {}", path.display());
        return;
    }
    let current = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e}; create it with `{REGEN}`", path.display()));
    if current != generated {
        let (line, (a, b)) = current
            .lines()
            .chain(std::iter::repeat("<end of file>"))
            .zip(generated.lines().chain(std::iter::repeat("<end of file>")))
            .enumerate()
            .find(|(_, (a, b))| a != b)
            .expect("the headers differ, so some line differs");
        panic!(
            "include/dcol.h differs from the header generated from src/ffi, first at line {}:\n  \
             checked in: {a}\n  generated:  {b}\nRegenerate it with `{REGEN}` and commit it.",
            line + 1
        );
    }
}

/// The `version = "..."` of the `[package]` table of Cargo.toml, read from the file itself.
fn cargo_toml_version() -> String {
    let text =
        std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("Cargo.toml"))
            .expect("read Cargo.toml");
    let mut in_package = false;
    for line in text.lines().map(str::trim) {
        if line.starts_with('[') {
            in_package = line == "[package]";
        } else if in_package && line.starts_with("version") {
            let value = line.split_once('=').expect("version = \"...\"").1.trim();
            return value.trim_matches('"').to_string();
        }
    }
    panic!("no version in the [package] table of Cargo.toml");
}

fn macro_value<'a>(header: &'a str, name: &str) -> &'a str {
    header
        .lines()
        .find_map(|l| l.strip_prefix(&format!("#define {name} ")))
        .unwrap_or_else(|| panic!("the header does not define {name}"))
        .trim()
}

#[test]
fn version_macros_match_cargo_toml() {
    // The generated header: the checked-in one equals it (previous test), and reading the
    // checked-in file here would race with a DCOL_BLESS run rewriting it.
    let header = generated();
    let version = cargo_toml_version();
    let parts: Vec<&str> = version.split(['.', '-', '+']).collect();
    assert!(
        parts.len() >= 3,
        "version {version} is not MAJOR.MINOR.PATCH"
    );
    let hint = format!("the version in Cargo.toml is {version}; regenerate with `{REGEN}`");
    assert_eq!(
        macro_value(&header, "DCOL_VERSION_MAJOR"),
        parts[0],
        "{hint}"
    );
    assert_eq!(
        macro_value(&header, "DCOL_VERSION_MINOR"),
        parts[1],
        "{hint}"
    );
    assert_eq!(
        macro_value(&header, "DCOL_VERSION_PATCH"),
        parts[2],
        "{hint}"
    );
    assert_eq!(
        macro_value(&header, "DCOL_VERSION_STRING"),
        format!("\"{version}\""),
        "{hint}"
    );
}

#[test]
fn header_declares_the_whole_contract() {
    let header = generated();
    for name in [
        "typedef enum dcol_status",
        "DCOL_OK = 0",
        "DCOL_ERROR_NULL_POINTER = 1",
        "DCOL_ERROR_INVALID_SHAPE = 2",
        "DCOL_ERROR_INVALID_POSE = 3",
        "DCOL_ERROR_INVALID_OPTIONS = 4",
        "DCOL_ERROR_NOT_CONVERGED = 5",
        "DCOL_ERROR_INTERNAL = 6",
        "const char *dcol_status_string(enum dcol_status status);",
        "const char *dcol_last_error_message(void);",
        "const char *dcol_version(void);",
        "typedef struct dcol_shape dcol_shape;",
        "dcol_shape_new_sphere(",
        "dcol_shape_new_ellipsoid(",
        "dcol_shape_new_polytope(",
        "dcol_shape_new_box(",
        "dcol_shape_new_capsule(",
        "dcol_shape_new_cylinder(",
        "dcol_shape_new_cone(",
        "dcol_shape_new_polygon(",
        "void dcol_shape_free(struct dcol_shape *shape);",
        "typedef struct dcol_pose",
        "typedef struct dcol_options",
        "struct dcol_options dcol_options_default(void);",
        "typedef struct dcol_proximity_result",
        "enum dcol_status dcol_proximity(",
        "enum dcol_status dcol_gradient(",
        "enum dcol_status dcol_jacobian(",
        "typedef struct dcol_distance_result",
        "enum dcol_status dcol_distance(",
        "#ifndef DCOL_H",
        "extern \"C\" {",
    ] {
        assert!(header.contains(name), "the header lacks `{name}`");
    }
}
