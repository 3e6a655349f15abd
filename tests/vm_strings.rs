//! The string instructions' quick ways (a built string handed to its cell without a copy,
//! a string handle read without the library's conversion, `STR$` digits pushed at once, the
//! string functions' checks of a count or position inlined) give what the build before gave:
//! the strings of a loop whose results are of every length in turn (a cell's buffer is reused
//! by the next string built), `STR$` at the edges of its plain-digit form, characters past
//! ASCII, fractional counts and positions, an illegal code, and the same instruction count.
//! The expected output is that of the build before these changes (f4b2615).

mod common;

use common::{load_memory, run_loaded, slot_value, Run};
use pacer::trace::Trace;
use pacer::vm::Machine;

/// The `print` events' texts.
fn printed(r: &Run) -> Vec<String> {
    r.events
        .iter()
        .filter(|e| e["kind"] == "print")
        .map(|e| e["text"].as_str().unwrap_or_default().to_string())
        .collect()
}

const PROGRAM: &str = "L& = 0\n\
         H& = 0\n\
         FOR I& = 1 TO 30\n\
           A$ = LEFT$(\"ABCDEFGHIJ\", I& MOD 11) + STR$(I& * 37 - 500) + CHR$(65 + I& MOD 26)\n\
           B$ = MID$(A$, 2) + RIGHT$(A$, 3) + MID$(A$, 1 + I& MOD 4, 2)\n\
           L& = L& + LEN(A$) * 3 + LEN(B$) + INSTR(B$, \"C\") + INSTR(A$, \"-4\")\n\
           H& = (H& * 31 + ASC(B$ + \"!\") + VAL(MID$(A$, INSTR(A$, \" \") + 1))) MOD 1000003\n\
           IF I& MOD 7 = 0 THEN PRINT A$; \"|\"; B$; \"|\"; L&; H&\n\
         NEXT\n\
         PRINT STR$(0); STR$(-0); STR$(9999999); STR$(10000000); STR$(-1234567); STR$(2.5)\n\
         N& = 2147483647\n\
         D# = 8999999999999999\n\
         PRINT STR$(N&); STR$(-N&); STR$(D#); STR$(D# + 1)\n\
         C$ = CHR$(200)\n\
         PRINT LEN(C$); ASC(C$); INSTR(C$ + \"x\", \"x\"); LEFT$(C$ + \"yz\", 2.5); MID$(\"abcdef\", 2.5, 1.5)\n\
         PRINT CHR$(256)\n";

#[test]
fn string_functions_give_the_strings_of_the_build_before() {
    let run = match load_memory(
        "vm-strings",
        &[
            ("program0.mb", PROGRAM),
            ("scenario.toml", "[run]\nduration = 0.05\n"),
        ],
    ) {
        Ok(l) => run_loaded(l),
        Err(d) => panic!("{}", d.render_plain()),
    };
    assert_eq!(
        printed(&run),
        [
            "ABCDEFG-241H|BCDEFG-241H41HDE| 301  48071 ",
            "ABC 18O|BC 18O18OC | 592  775791 ",
            "ABCDEFGHIJ 277V|BCDEFGHIJ 277V77VBC| 962  145065 ",
            "ABCDEF 536C|BCDEF 536C36CAB| 1222  929866 ",
            " 0 0 9999999 10000000-1234567 2.5",
            " 2147483647-2147483647 8999999999999999 9000000000000000",
            " 1  200  2 \u{c8}ybc",
        ]
    );
    let e = run.summary.error.as_ref().expect("CHR$(256) stops the run");
    assert_eq!(e.line, 16);
    assert_eq!(
        e.message,
        "Illegal function call: CHR$ takes a code from 0 to 255, not 256"
    );
    assert_eq!(run.summary.instructions, 2412);
}

/// A join appends in place to the string its left side just built (a function's result or an
/// earlier join); every variable and element keeps its own string, a join past 255 characters
/// fails where it did, and a string function still counts its arguments: a budget of 7 yields
/// where the build that copied them into argument registers yielded (3 updates, 112
/// instructions, both as 3fdd2ab counted them).
#[test]
fn joins_build_in_place_and_count_as_before() {
    let program = "DIM E$(2)\n\
         FOR I& = 1 TO 3\n\
           A$ = LEFT$(\"XYZ\", I&) + \"-\" + STR$(I&) + A$\n\
           E$(I& MOD 2) = CHR$(96 + I&) + CHR$(96 + I&) + E$(I& MOD 2)\n\
         NEXT\n\
         PRINT A$; \"|\"; E$(0); \"|\"; E$(1)\n\
         MID$(E$(1), 2) = \"QQ\"\n\
         B$ = E$(1)\n\
         MID$(B$, 1, 1) = \"Z\"\n\
         PRINT B$; \"|\"; E$(1)\n\
         S$ = STRING$(200, \"a\") + STRING$(50, 66) + \"12345\" + \"6\"\n";
    let machine = "[machine]\nname = \"joins\"\nbudget = 7\n\
                   [[program]]\nnumber = 0\nfile = \"program0.mb\"\n";
    let load = || match load_memory(
        "vm-strings-joins",
        &[
            ("program0.mb", program),
            ("machine.toml", machine),
            ("scenario.toml", "[run]\nduration = 0.05\n"),
        ],
    ) {
        Ok(l) => l,
        Err(d) => panic!("{}", d.render_plain()),
    };
    // Untraced, a store does not ask whether the string changed: the same strings are left.
    let loaded = load();
    let tick = loaded.image.tick_ns;
    let mut untraced = Machine::new(loaded.image, Trace::new(None, tick));
    untraced.run_observed(None, &mut |_| {});
    let text_of = |m: &Machine, name: &str| {
        let slot = slot_value(m, name).unwrap_or_else(|| panic!("no {name}"));
        m.strings()[slot as usize].clone()
    };
    assert_eq!(text_of(&untraced, "A$"), "XYZ- 3XY- 2X- 1");
    assert_eq!(text_of(&untraced, "B$"), "ZQQa");
    assert_eq!(text_of(&untraced, "S$"), "");
    let run = run_loaded(load());
    assert_eq!(text_of(&run.machine, "A$"), "XYZ- 3XY- 2X- 1");
    assert_eq!(printed(&run), ["XYZ- 3XY- 2X- 1|bb|ccaa", "ZQQa|cQQa"]);
    let e = run
        .summary
        .error
        .as_ref()
        .expect("the 256-character join stops the run");
    assert_eq!((e.line, e.column), (11, 6));
    assert_eq!(
        e.message,
        "String too long: a string holds at most 255 characters"
    );
    assert_eq!((run.summary.instructions, run.summary.ticks), (112, 3));
}
