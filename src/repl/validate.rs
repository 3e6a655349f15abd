//! When a typed line is complete: the parser decides. A block (`If … Endif`, `Do While … Loop`,
//! `For … Next`, `IF … ENDIF`, `WHILE … WEND`) that the parser reports unclosed asks for
//! more lines; anything else, right or wrong, is complete and goes to be run (or reported).

use super::commands::PREFIX;
use crate::syntax::{parse_program_as, Dialect};

/// The parser's code for a block that is never closed.
const UNCLOSED: &str = "pacer::syntax::unclosed";

/// True when `text` opens a block it does not close, so the REPL should read more lines.
pub fn incomplete(text: &str, dialect: Dialect) -> bool {
    if text.trim_start().starts_with(PREFIX) {
        return false;
    }
    let mut problems = Vec::new();
    parse_program_as(text, dialect, &mut problems);
    problems.iter().any(|p| p.code == UNCLOSED)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_blocks_ask_for_more_lines() {
        let pt = Dialect::PowerTools;
        assert!(incomplete("If Bit.0 Then", pt));
        assert!(incomplete("If Bit.0 Then\nBit.1 = ON", pt));
        assert!(!incomplete("If Bit.0 Then\nBit.1 = ON\nEndif", pt));
        assert!(incomplete("Do While Bit.0", pt));
        assert!(!incomplete("Bit.1 = ON", pt));
        // A syntax error is complete: it is reported, not waited on.
        assert!(!incomplete("Bit.1 = = ON", pt));
        // A keyword in a comment opens nothing.
        assert!(!incomplete("Bit.1 = ON ' If this Then", pt));
        assert!(!incomplete(":step 5", pt));
        let mb = Dialect::MotionBasic;
        assert!(incomplete("IF X& > 1 THEN", mb));
        assert!(!incomplete("IF X& > 1 THEN Y& = 2", mb));
        // An ELSEIF goes on with the block; its END IF closes the chain.
        assert!(incomplete("IF X& > 1 THEN\nY& = 2\nELSEIF X& < 0 THEN", mb));
        assert!(!incomplete(
            "IF X& > 1 THEN\nY& = 2\nELSEIF X& < 0 THEN\nY& = 1\nEND IF",
            mb
        ));
        assert!(incomplete("WHILE X& < 3", mb));
        assert!(!incomplete("WHILE X& < 3\nX& = X& + 1\nWEND", mb));
        // A SELECT CASE goes on until its END SELECT, whatever its CASEs.
        assert!(incomplete("SELECT CASE X&", mb));
        assert!(incomplete("SELECT CASE X&\nCASE 1\nY& = 2\nCASE ELSE", mb));
        assert!(!incomplete(
            "SELECT CASE X&\nCASE 1\nY& = 2\nEND SELECT",
            mb
        ));
    }
}
