//! The statement families of the two languages that pacer knows by name but does not run yet
//! (docs/coverage.md's "not yet" rows). A program that uses one gets an error that says so,
//! instead of the grammar's or the checker's generic complaint about an unknown word.

/// ORMEC MotionBASIC's motion statements pacer does not run: the manual's keyword index names
/// them, no public source gives their syntax.
const MOTIONBASIC: &[&str] = &["BLEND", "CAM", "PROFILE", "REPEAT"];

/// The error message for a Microsoft BASIC keyword pacer knows but does not run (the MotionBASIC
/// lexer makes [`crate::syntax::token::Tok::Unsupported`] of it), if `word` is one.
pub fn basic(word: &str) -> Option<String> {
    let w = word.to_ascii_uppercase();
    Some(match w.as_str() {
        "ERROR" | "RESUME" | "ERR" | "ERL" => format!(
            "`{w}` belongs to error trapping (`ON ERROR GOTO`, `RESUME`, `ERROR n`, `ERR`, \
             `ERL`), which pacer does not run: a run-time error stops the program and is \
             reported at its place; test the values before the statement that would fail"
        ),
        "DEF" => "`DEF FN` functions are not run by pacer: write the expression where it is \
                  used, or a GOSUB that leaves its result in a variable"
            .into(),
        "SUB" | "FUNCTION" => format!(
            "QuickBASIC's `{w}` procedures are not run by pacer: use a label, GOSUB and \
             RETURN, passing values in variables"
        ),
        _ => return None,
    })
}

/// PowerTools objects of the cam feature.
const POWERTOOLS: &[&str] = &["Cam", "CamTable"];

/// Where a user reads what pacer runs.
pub const HELP: &str = "docs/coverage.md lists the statement families pacer runs";

/// The error message for MotionBASIC word `word` at the start of a statement, if it is a
/// statement pacer does not run yet.
pub fn motionbasic(word: &str) -> Option<String> {
    let known = MOTIONBASIC.iter().find(|k| k.eq_ignore_ascii_case(word))?;
    Some(format!(
        "`{known}` is an ORMEC MotionBASIC motion statement that pacer does not run yet \
         ({})",
        MOTIONBASIC.join(", ")
    ))
}

/// The error message for PowerTools object `object`, if it belongs to a feature pacer does not
/// run yet.
pub fn powertools(object: &str) -> Option<String> {
    let known = POWERTOOLS.iter().find(|k| k.eq_ignore_ascii_case(object))?;
    Some(format!(
        "cams (`{known}`) are a PowerTools feature that pacer does not run yet"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_found_in_any_case_and_others_are_not() {
        assert!(motionbasic("cam").is_some_and(|m| m.starts_with("`CAM` is")));
        assert!(motionbasic("Repeat").is_some());
        assert_eq!(motionbasic("GEAR"), None);
        assert!(powertools("cam").is_some_and(|m| m.contains("`Cam`")));
        assert_eq!(powertools("Index"), None);
        assert!(basic("Resume").is_some_and(|m| m.starts_with("`RESUME` belongs to error")));
        assert!(basic("def").is_some_and(|m| m.contains("`DEF FN`")));
        assert!(basic("function").is_some_and(|m| m.contains("`FUNCTION` procedures")));
        assert_eq!(basic("GOSUB"), None);
    }
}
