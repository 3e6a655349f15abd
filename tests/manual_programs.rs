//! A machine builder's own programs (issue 16): what `pacer check` and `pacer run` do with
//! files as users bring them — loose files without their machine, files from old Windows
//! editors.

mod common;

/// `pacer check` of loose files without a machine file: a program initiating or calling one not
/// given is a warning (the others may have it), and in a folder it is an error (issue 16).
#[test]
fn checking_one_file_warns_about_programs_not_given() {
    let program = "Program.1.Initiate\nCall Program.2\n";
    let dir = common::project("loose-files", &[("program0.pt", program)]);
    let file = dir.join("program0.pt").to_string_lossy().to_string();
    let out = common::pacer(&["check", &file]);
    let text = common::text(&out);
    assert!(out.status.success(), "{text}");
    assert!(
        text.contains("Program.1 is not among the files given"),
        "{text}"
    );
    assert!(
        text.contains("Program.2 is not among the files given"),
        "{text}"
    );
    let folder = dir.to_string_lossy().to_string();
    let out = common::pacer(&["check", &folder]);
    let text = common::text(&out);
    assert!(!out.status.success(), "{text}");
    assert!(
        text.contains("Program.1 is not loaded on this machine"),
        "{text}"
    );
}

/// A program saved as Windows-1252 (a `°` in a comment, CRLF lines) is read, with a warning
/// naming the file and the first byte that is not UTF-8 at its line and column.
#[test]
fn a_windows_1252_program_is_read_with_a_warning_at_the_byte() {
    let dir = common::project("cp1252", &[]);
    std::fs::write(
        dir.join("program0.pt"),
        b"' speed in \xb0/s\r\nDriveOutput.1 = ON\r\n",
    )
    .expect("program written");
    let folder = dir.to_string_lossy().to_string();
    let loaded = pacer::load::load(&pacer::load::LoadRequest {
        paths: vec![dir.clone()],
        ..Default::default()
    })
    .unwrap_or_else(|d| panic!("{}", d.render_plain()));
    let warnings: Vec<_> = loaded.warnings.items.iter().map(|l| &l.problem).collect();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert_eq!(warnings[0].code, "pacer::load::encoding");
    assert_eq!(
        warnings[0].message,
        format!(
            "{} is not UTF-8: read as Windows-1252 (its first such byte, 0xB0, is `\u{b0}` at line 1, column 12)",
            dir.join("program0.pt").display()
        )
    );
    assert_eq!((warnings[0].span.start, warnings[0].span.end), (11, 13));
    let out = common::pacer(&["run", &folder, "-q", "--trace", "/dev/stdout"]);
    let text = common::text(&out);
    assert!(
        text.contains("\"name\":\"DriveOutput.1\",\"value\":true"),
        "{text}"
    );
}
