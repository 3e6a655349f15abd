//! The plots of the three example machines checked in under `docs/` (and shown in the README)
//! are what pacer draws today, byte for byte, with the commands the README gives. When a change
//! of behaviour or of the pictures is intended, redraw them and look at them before committing:
//!
//! ```sh
//! PACER_BLESS=1 cargo test --test export_docs
//! ```

use std::path::Path;
use std::process::Command;

/// The README's commands, `docs/…svg` being the plot each writes.
const PICTURES: &[(&str, &[&str])] = &[
    (
        "docs/labeling.svg",
        &[
            "run",
            "programs/labeling",
            "--for",
            "46",
            "--window",
            "38:46",
        ],
    ),
    (
        "docs/web-registration.svg",
        &["run", "programs/web-registration"],
    ),
    (
        "docs/pick-and-place.svg",
        &["run", "programs/pick-and-place/delta-cv1-cv2", "--for", "5"],
    ),
];

#[test]
fn the_pictures_in_docs_are_what_pacer_draws() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("pacer-export-docs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let bless = std::env::var_os("PACER_BLESS").is_some();
    for (doc, args) in PICTURES {
        let drawn = dir.join(Path::new(doc).file_name().expect("a file name"));
        let out = Command::new(env!("CARGO_BIN_EXE_pacer"))
            .current_dir(root)
            .args(*args)
            .args(["-q", "--plot"])
            .arg(&drawn)
            .output()
            .expect("pacer runs");
        assert!(
            out.status.success(),
            "{doc}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let svg = std::fs::read(&drawn).expect("the plot");
        if bless {
            std::fs::write(root.join(doc), &svg).expect("write docs");
            continue;
        }
        let kept = std::fs::read(root.join(doc)).unwrap_or_default();
        assert!(
            kept == svg,
            "{doc} is not what `pacer {} --plot {doc}` draws now: redraw with \
             PACER_BLESS=1 cargo test --test export_docs, and look at it",
            args.join(" ")
        );
    }
}
