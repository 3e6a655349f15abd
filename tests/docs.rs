//! The README and the pages under `docs/` against the code they describe. The test fails when
//! something a reader needs is missing:
//!
//! 1. every object type of the catalog (`src/registry/catalog.rs`) and every member of it is in
//!    the docs: the object reference is *generated* from the catalog into a marked region of
//!    `docs/objects.md` (and of `docs/pick-and-place.md` for the module and its belts), and the
//!    page must hold what the catalog renders today;
//! 2. every flag of every subcommand, as the built binary's `--help` lists it, is in
//!    `docs/cli.md`, in the section of its subcommand;
//! 3. every trace kind (`EventKind::ALL`) is in the table of `docs/trace.md`, with every field
//!    its typical event (`Event::example`) carries;
//! 4. `README.md` stays under 15,000 bytes (it is the front door; the reference is in `docs/`);
//! 5. every relative link in `README.md` and `docs/*.md` points to a file that exists;
//! 6. every REPL command is in `docs/repl.md`, every function in `docs/powertools.md`.
//!
//! After a change of the catalog, rewrite the generated regions and read the diff:
//!
//! ```sh
//! PACER_BLESS=1 cargo test --test docs
//! git diff docs
//! ```

use pacer::registry::catalog::{self, Access, Instances, Kind, MemberDef, TypeDef, ValueType};
use pacer::trace::{Event, EventKind};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The start of a generated region.
const BEGIN: &str = "<!-- catalog:begin -->";
/// The end of a generated region.
const END: &str = "<!-- catalog:end -->";

/// The README's size limit, bytes.
const README_LIMIT: usize = 15_000;

/// The repository's root.
fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// A file of the repository as text.
fn read(rel: &str) -> String {
    std::fs::read_to_string(root().join(rel)).unwrap_or_else(|e| panic!("read {rel}: {e}"))
}

/// `README.md` and every `docs/*.md`, as (path relative to the root, text), sorted.
fn pages() -> Vec<(String, String)> {
    let mut names: Vec<String> = std::fs::read_dir(root().join("docs"))
        .expect("a docs folder")
        .map(|e| e.expect("a readable docs folder").file_name())
        .map(|n| n.to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".md"))
        .map(|n| format!("docs/{n}"))
        .collect();
    names.sort();
    names.insert(0, "README.md".to_string());
    names.into_iter().map(|n| (n.clone(), read(&n))).collect()
}

// ---------------------------------------------------------------------------------------------
// 1. The object reference, generated from the catalog.

/// A page with a generated region, and which object types it holds.
struct Region {
    /// The page, relative to the root.
    page: &'static str,
    /// The types rendered into it.
    holds: fn(&TypeDef) -> bool,
}

/// The pick & place module and its belts have a page of their own.
fn is_pick_place(t: &TypeDef) -> bool {
    matches!(t.kind, Kind::PickPlace | Kind::Belt)
}

/// Every other type is on the object page.
fn is_not_pick_place(t: &TypeDef) -> bool {
    !is_pick_place(t)
}

/// Where the catalog goes. Every type is held by exactly one region (checked).
const REGIONS: &[Region] = &[
    Region {
        page: "docs/objects.md",
        holds: is_not_pick_place,
    },
    Region {
        page: "docs/pick-and-place.md",
        holds: is_pick_place,
    },
];

/// One row of a member table: a member, or the elements of an array member together.
struct Row {
    name: String,
    ty: ValueType,
    access: Access,
    doc: String,
}

/// The value type as the tables write it.
fn type_word(ty: ValueType) -> String {
    match ty {
        ValueType::Bit => "bit".into(),
        ValueType::Integer => "integer".into(),
        ValueType::Fixed(d) => format!("fixed, {d} decimals"),
        ValueType::Real => "real".into(),
    }
}

/// The access as the tables write it (the page's introduction explains the words).
fn access_word(access: Access) -> &'static str {
    match access {
        Access::Read => "status",
        Access::ReadWrite => "setting",
        Access::Action => "action",
        Access::Input => "input",
    }
}

/// Text safe inside a table cell.
fn cell(text: &str) -> String {
    text.replace('|', "\\|").replace('<', "\\<")
}

/// A catalog line as a sentence: capital first letter, full stop.
fn sentence(doc: &str) -> String {
    let mut chars = doc.chars();
    let mut out: String = match chars.next() {
        Some(c) => c.to_uppercase().chain(chars).collect(),
        None => String::new(),
    };
    if !out.ends_with('.') {
        out.push('.');
    }
    out
}

/// The elements `base[1]` … `base[n]` starting at `members[0]`, as one row, when they share
/// their type, access and documentation up to the axis in parentheses that ends each line
/// (`current position of the axis, units (X)`). None when `members[0]` starts no such array.
fn array_row(members: &[MemberDef]) -> Option<(Row, usize)> {
    let (base, index) = catalog::split_index(members.first()?.name)?;
    if index != "1" {
        return None;
    }
    let (_, len) = catalog::find_array(members, base)?;
    let first = &members[0];
    let mut common: Option<&str> = None;
    let mut labels = Vec::with_capacity(len);
    for m in &members[..len] {
        let (text, label) = m.doc.strip_suffix(')')?.rsplit_once(" (")?;
        if m.ty != first.ty || m.access != first.access || !m.aliases.is_empty() {
            return None;
        }
        if *common.get_or_insert(text) != text {
            return None;
        }
        labels.push(label);
    }
    let row = Row {
        name: format!("{base}[1..{len}]"),
        ty: first.ty,
        access: first.access,
        doc: format!("{}; 1–{len}: {}", common?, labels.join(", ")),
    };
    Some((row, len))
}

/// The rows of a member list: arrays together, everything else one row per member.
fn rows(members: &[MemberDef]) -> Vec<Row> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < members.len() {
        if let Some((row, len)) = array_row(&members[i..]) {
            out.push(row);
            i += len;
            continue;
        }
        let m = &members[i];
        let also: Vec<String> = m.aliases.iter().map(|a| format!("`{a}`")).collect();
        out.push(Row {
            name: m.name.to_string(),
            ty: m.ty,
            access: m.access,
            doc: if also.is_empty() {
                m.doc.to_string()
            } else {
                format!("{} (also written {})", m.doc, also.join(", "))
            },
        });
        i += 1;
    }
    out
}

/// A member table.
fn table(members: &[MemberDef]) -> String {
    let mut out = String::from("| member | type | access | what it is |\n|---|---|---|---|\n");
    for r in rows(members) {
        out.push_str(&format!(
            "| `{}` | {} | {} | {} |\n",
            r.name,
            type_word(r.ty),
            access_word(r.access),
            cell(&r.doc)
        ));
    }
    out
}

/// How the instances of a type are written.
fn instances(t: &TypeDef) -> String {
    let example = |inst: &str| match t.default_member {
        Some(d) => format!(" `{}.{inst}` alone means `{}.{inst}.{d}`.", t.name, t.name),
        None => String::new(),
    };
    match t.instances {
        Instances::Global => {
            let first = t.members.first().map_or("Member", |m| m.name);
            let bare = if t.name == catalog::BARE_GLOBAL_TYPE {
                format!(", or bare: `{first}`")
            } else {
                String::new()
            };
            format!(
                "One object, no instance number: `{}.{first}`{bare}.",
                t.name
            )
        }
        Instances::Numbered {
            first,
            default_count: 0,
        } => format!(
            "Numbered from `{}.{first}`; none unless machine.toml declares them.{}",
            t.name,
            example(&first.to_string())
        ),
        Instances::Numbered {
            first,
            default_count: 1,
        } => format!(
            "One instance by default, `{}.{first}`.{}",
            t.name,
            example(&first.to_string())
        ),
        Instances::Numbered {
            first,
            default_count,
        } => format!(
            "{default_count} instances by default: `{n}.{first}` … `{n}.{last}`.{}",
            example(&first.to_string()),
            n = t.name,
            last = first + default_count - 1,
        ),
        Instances::Named => format!("Named instances: `{}.NAME`.{}", t.name, example("NAME")),
    }
}

/// One object type: heading, what it is, its instances, its members.
fn render_type(t: &TypeDef) -> String {
    let mut out = format!(
        "### `{}`\n\n{} {}\n\n",
        t.name,
        sentence(t.doc),
        instances(t)
    );
    if t.referable {
        let how = match t.kind {
            Kind::Capture => format!("`Index.0.Initiate Using {}.1`", t.name),
            Kind::Profile => format!("`Index.0.Initiate On {}.1`", t.name),
            _ => format!("`Using {0}.N` / `On {0}.N`", t.name),
        };
        out.push_str(&format!(
            "A motion statement can name its instances: {how}.\n\n"
        ));
    }
    out.push_str(&table(t.members));
    if !t.global_members.is_empty() {
        let first = t.global_members[0].name;
        out.push_str(&format!(
            "\nMembers of the type itself, written without an instance (`{}.{first}`):\n\n",
            t.name
        ));
        out.push_str(&table(t.global_members));
    }
    out
}

/// What a region holds: a note on where it comes from, then every type it holds.
fn render_region(holds: fn(&TypeDef) -> bool) -> String {
    let mut out = String::from(
        "\n_Generated from `src/registry/catalog.rs` by `tests/docs.rs`: change the catalog, \
         then `PACER_BLESS=1 cargo test --test docs`._\n",
    );
    for t in catalog::TYPES.iter().filter(|t| holds(t)) {
        out.push('\n');
        out.push_str(&render_type(t));
    }
    out.push('\n');
    out
}

/// The page with its region replaced by `body`; None when the page has no region.
fn with_region(page: &str, body: &str) -> Option<String> {
    let start = page.find(BEGIN)? + BEGIN.len();
    let end = start + page[start..].find(END)?;
    Some(format!("{}{body}{}", &page[..start], &page[end..]))
}

#[test]
fn the_object_reference_is_what_the_catalog_renders() {
    let bless = std::env::var_os("PACER_BLESS").is_some();
    for t in catalog::TYPES {
        let n = REGIONS.iter().filter(|r| (r.holds)(t)).count();
        assert_eq!(n, 1, "{} is held by {n} regions, not 1", t.name);
    }
    let mut stale = Vec::new();
    for region in REGIONS {
        let page = read(region.page);
        let rendered = with_region(&page, &render_region(region.holds)).unwrap_or_else(|| {
            panic!(
                "{} has no generated region: put {BEGIN} and {END} where the object \
                 tables go",
                region.page
            )
        });
        if rendered == page {
            continue;
        }
        if bless {
            std::fs::write(root().join(region.page), &rendered)
                .unwrap_or_else(|e| panic!("write {}: {e}", region.page));
        } else {
            let line = page
                .lines()
                .zip(rendered.lines())
                .position(|(a, b)| a != b)
                .map_or(page.lines().count().min(rendered.lines().count()), |i| i)
                + 1;
            stale.push(format!("{} (first difference at line {line})", region.page));
        }
    }
    assert!(
        stale.is_empty(),
        "the object reference is not what the catalog renders: {}\nrewrite it with \
         PACER_BLESS=1 cargo test --test docs, and read the diff",
        stale.join(", ")
    );
}

/// The section of `text` under the heading line that contains `heading`, up to the next heading
/// of the same or a higher level.
fn section<'a>(text: &'a str, heading: &str) -> Option<&'a str> {
    let mut at = 0;
    let mut start = None;
    let mut level = 0;
    for line in text.split_inclusive('\n') {
        let hashes = line.chars().take_while(|&c| c == '#').count();
        let is_heading = hashes > 0 && line[hashes..].starts_with(' ');
        match start {
            None if is_heading && line.contains(heading) => {
                start = Some(at + line.len());
                level = hashes;
            }
            Some(s) if is_heading && hashes <= level => return Some(&text[s..at]),
            _ => {}
        }
        at += line.len();
    }
    start.map(|s| &text[s..])
}

/// True when `docs` names `member` in backquotes: as itself, or an array element `base[k]` as a
/// range `base[a..b]` with a ≤ k ≤ b.
fn names_member(docs: &str, member: &str) -> bool {
    if docs.contains(&format!("`{member}`")) {
        return true;
    }
    let Some((base, k)) = catalog::split_index(member) else {
        return false;
    };
    let Ok(k) = k.parse::<u32>() else {
        return false;
    };
    let open = format!("`{base}[");
    docs.match_indices(&open).any(|(i, _)| {
        let rest = &docs[i + open.len()..];
        let range = rest.split_once("]`").map_or("", |(r, _)| r);
        match range.split_once("..").map(|(a, b)| (a.parse(), b.parse())) {
            Some((Ok(a), Ok(b))) => (a..=b).contains(&k),
            _ => false,
        }
    })
}

#[test]
fn every_object_type_and_member_is_in_the_docs() {
    let docs: String = pages().into_iter().map(|(_, text)| text + "\n").collect();
    let mut missing = Vec::new();
    for t in catalog::TYPES {
        let Some(text) = section(&docs, &format!("### `{}`", t.name)) else {
            missing.push(format!(
                "the type {} (no `### `{}`` heading)",
                t.name, t.name
            ));
            continue;
        };
        for m in t.members.iter().chain(t.global_members) {
            for name in std::iter::once(&m.name).chain(m.aliases) {
                if !names_member(text, name) {
                    missing.push(format!("{}.{name}", t.name));
                }
            }
        }
    }
    assert!(
        missing.is_empty(),
        "not in the docs: {}",
        missing.join(", ")
    );
}

// ---------------------------------------------------------------------------------------------
// 2. The command line, from the binary's own help.

/// `pacer ARGS… --help`, as printed.
fn help(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_pacer"))
        .args(args)
        .arg("--help")
        .output()
        .expect("pacer runs");
    assert!(
        out.status.success(),
        "pacer {} --help failed",
        args.join(" ")
    );
    String::from_utf8(out.stdout).expect("help is UTF-8")
}

/// The lines of a help section (`Commands:`, `Options:`), up to the next blank line.
fn help_section<'a>(help: &'a str, title: &str) -> Vec<&'a str> {
    help.lines()
        .skip_while(|l| l.trim() != title)
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .collect()
}

/// The subcommands `pacer --help` lists (`help` itself left out).
fn subcommands() -> Vec<String> {
    help_section(&help(&[]), "Commands:")
        .iter()
        .filter(|l| l.starts_with("  ") && !l.starts_with("   "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .map(str::to_string)
        .collect()
}

/// The flags of a help text's `Options:` section: `--long` and `-x`, as they start each option
/// line (`-q, --quiet`, `--for <SECONDS>`).
fn flags(help: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in help_section(help, "Options:") {
        if !line.trim_start().starts_with('-') {
            continue; // a wrapped line of help text
        }
        for word in line.split_whitespace() {
            let word = word.trim_end_matches(',');
            let long = word.starts_with("--")
                && word.len() > 2
                && word[2..]
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '-');
            let short = word.len() == 2
                && word.starts_with('-')
                && word[1..].chars().all(|c| c.is_ascii_alphanumeric());
            if long || short {
                out.push(word.to_string());
            } else if !(word.starts_with('<') || word.starts_with('[')) {
                break; // the help text begins
            }
        }
    }
    out
}

/// True when `text` has `flag` as a whole word (`-q` is not found in `-quiet` or `--q`).
fn has_flag(text: &str, flag: &str) -> bool {
    text.match_indices(flag).any(|(i, _)| {
        let before = text[..i].chars().next_back();
        let after = text[i + flag.len()..].chars().next();
        !before.is_some_and(|c| c == '-' || c.is_ascii_alphanumeric())
            && !after.is_some_and(|c| c == '-' || c.is_ascii_alphanumeric())
    })
}

#[test]
fn every_flag_of_every_subcommand_is_in_cli_md() {
    let page = read("docs/cli.md");
    let subs = subcommands();
    for expected in ["run", "check", "disasm", "repl", "plot"] {
        assert!(
            subs.iter().any(|s| s == expected),
            "`pacer --help` does not list {expected}: {subs:?}"
        );
    }
    let mut missing = Vec::new();
    for flag in flags(&help(&[])) {
        if !has_flag(&page, &flag) {
            missing.push(format!("pacer {flag}"));
        }
    }
    for sub in &subs {
        let heading = format!("## `pacer {sub}`");
        let Some(text) = section(&page, &heading) else {
            missing.push(format!("the section {heading}"));
            continue;
        };
        let found = flags(&help(&[sub]));
        assert!(
            !found.is_empty(),
            "no flags parsed from `pacer {sub} --help`"
        );
        for flag in found {
            if !has_flag(text, &flag) {
                missing.push(format!("pacer {sub} {flag}"));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "not in docs/cli.md: {}",
        missing.join(", ")
    );
}

// ---------------------------------------------------------------------------------------------
// 3. The trace kinds.

/// The rows of the trace table of `page` (docs/trace.md): for each kind written in backquotes
/// in the first cell (`` | `pick` / `place` | ``), the row's second cell.
fn trace_rows(page: &str) -> Vec<(String, String)> {
    page.lines()
        .filter(|l| l.starts_with('|'))
        .filter_map(|l| {
            let mut cells = l.split('|').skip(1);
            Some((cells.next()?, cells.next()?))
        })
        .flat_map(|(first, fields)| {
            first
                .split('`')
                .skip(1)
                .step_by(2)
                .map(move |kind| (kind.to_string(), fields.to_string()))
        })
        .collect()
}

/// What `page` lacks for the events `examples` (kind, JSON of a typical event): a kind without a
/// row, or a field of the event (other than `t`, `tick` and `kind`) not in backquotes in its row.
fn undocumented_trace(examples: &[(String, serde_json::Value)], page: &str) -> Vec<String> {
    let rows = trace_rows(page);
    let mut missing = Vec::new();
    for (kind, json) in examples {
        let Some((_, fields)) = rows.iter().find(|(k, _)| k == kind) else {
            missing.push(format!("kind `{kind}`"));
            continue;
        };
        let Some(object) = json.as_object() else {
            missing.push(format!("kind `{kind}` is not a JSON object"));
            continue;
        };
        for key in object.keys() {
            if ["t", "tick", "kind"].contains(&key.as_str()) {
                continue;
            }
            if !fields.contains(&format!("`{key}`")) {
                missing.push(format!("field `{key}` of `{kind}`"));
            }
        }
    }
    missing
}

#[test]
fn every_trace_kind_and_field_is_in_trace_md() {
    let examples: Vec<(String, serde_json::Value)> = EventKind::ALL
        .iter()
        .map(|&kind| {
            let json = serde_json::to_value(Event::example(kind))
                .unwrap_or_else(|e| panic!("the example of {kind} serializes: {e}"));
            (kind.as_str().to_string(), json)
        })
        .collect();
    assert!(examples.len() >= 27, "EventKind::ALL lost kinds");
    let missing = undocumented_trace(&examples, &read("docs/trace.md"));
    assert!(
        missing.is_empty(),
        "not in the table of docs/trace.md: {}",
        missing.join(", ")
    );
}

#[test]
fn an_undocumented_trace_kind_or_field_is_found() {
    let page =
        "| kind | fields |\n|---|---|\n| `start` | `machine` |\n| `pick` / `place` | `x` |\n";
    let examples = vec![
        (
            "start".to_string(),
            serde_json::json!({"kind": "start", "machine": "m"}),
        ),
        (
            "place".to_string(),
            serde_json::json!({"kind": "place", "x": 1, "y": 2}),
        ),
        (
            "new_kind".to_string(),
            serde_json::json!({"kind": "new_kind"}),
        ),
    ];
    assert_eq!(
        undocumented_trace(&examples, page),
        ["field `y` of `place`", "kind `new_kind`"]
    );
}

// ---------------------------------------------------------------------------------------------
// 4. and 5. The README's size, and the links.

#[test]
fn the_readme_is_a_front_door() {
    let size = read("README.md").len();
    assert!(
        size < README_LIMIT,
        "README.md is {size} bytes; keep it under {README_LIMIT}: move reference text to docs/"
    );
}

/// Markdown without its fenced code blocks and inline code (where `](` is not a link).
fn prose(text: &str) -> String {
    let mut out = String::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        for (i, part) in line.split('`').enumerate() {
            if i % 2 == 0 {
                out.push_str(part);
            }
        }
        out.push('\n');
    }
    out
}

/// The targets of the links `[text](target)` and images `![alt](target)` of a page.
fn link_targets(text: &str) -> Vec<String> {
    let text = prose(text);
    text.match_indices("](")
        .filter_map(|(i, _)| {
            let rest = &text[i + 2..];
            let end = rest.find(')')?;
            let target = rest[..end].split_whitespace().next()?;
            Some(target.to_string())
        })
        .collect()
}

#[test]
fn every_relative_link_points_to_a_file() {
    let mut broken = Vec::new();
    for (page, text) in pages() {
        let dir = root().join(&page);
        let dir = dir.parent().expect("a page in a folder");
        for target in link_targets(&text) {
            if target.starts_with('#') || target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            let file = target.split('#').next().unwrap_or_default();
            let path: PathBuf = dir.join(file);
            if !path.exists() {
                broken.push(format!("{page}: {target}"));
            }
        }
    }
    assert!(broken.is_empty(), "broken links: {}", broken.join(", "));
}

#[test]
fn the_link_finder_skips_code() {
    let text = "[a](docs/a.md) `[b](no.md)` ![c](c.svg \"title\")\n```\n[d](no.md)\n```\n";
    assert_eq!(link_targets(text), ["docs/a.md", "c.svg"]);
}

// ---------------------------------------------------------------------------------------------
// 6. The REPL's commands and the functions.

#[test]
fn every_repl_command_is_in_repl_md() {
    let page = read("docs/repl.md");
    let missing: Vec<&str> = pacer::repl::commands::COMMANDS
        .iter()
        .map(|(name, _, _)| *name)
        .filter(|name| !page.contains(&format!("`:{name}")))
        .collect();
    assert!(
        missing.is_empty(),
        "REPL commands not in docs/repl.md: {}",
        missing.join(", ")
    );
}

#[test]
fn every_function_is_in_the_language_pages() {
    let docs = format!(
        "{}{}{}",
        read("docs/powertools.md"),
        read("docs/motionbasic.md"),
        read("docs/regist.md")
    );
    let names = pacer::check::functions::FUNCTIONS
        .iter()
        .map(|f| f.0)
        .chain(
            pacer::check::functions::KERNEL_FUNCTIONS
                .iter()
                .map(|f| f.0),
        );
    let missing: Vec<&str> = names.filter(|n| !has_flag(&docs, n)).collect();
    assert!(
        missing.is_empty(),
        "functions not in docs/powertools.md, motionbasic.md or regist.md: {}",
        missing.join(", ")
    );
}
