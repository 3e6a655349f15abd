//! The checked program: every name resolved (a member's slot, a MotionBASIC variable, a label,
//! a program), every expression typed, every operator given the meaning its dialect gives it.
//! The compiler turns it into bytecode without looking anything up again.

use super::functions::{Func, KernelFunc};
use super::text::TextFunc;
use crate::devices::command::{Domain, MotionCmd, StartRef};
use crate::registry::{Hook, Resolved, SlotId};
use crate::span::Span;

/// What a value is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ty {
    /// ON/OFF (PowerTools).
    Bool,
    /// A number (MotionBASIC's truth values are numbers too).
    Num,
    /// A string (MotionBASIC).
    Str,
    /// A set of axes (MotionBASIC).
    Axis,
}

/// A checked expression.
#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    /// What it computes.
    pub kind: ExprKind,
    /// Its type.
    pub ty: Ty,
    /// A MotionBASIC long integer: its arithmetic overflows outside 32 bits, as in Microsoft
    /// BASIC.
    pub long: bool,
    /// A MotionBASIC INTEGER (`%`) computed from INTEGER operands, at least one of them a `%`
    /// variable or element: Microsoft BASIC computes it in 16 bits, so a result outside -32768
    /// to 32767 is an Overflow even before it is stored.
    pub int16: bool,
    /// A constant Microsoft BASIC types as INTEGER: digits within 16 bits (`1000`), or written
    /// with `%`. It may be an operand of INTEGER arithmetic; `1000&` and `1000!` may not.
    pub int_const: bool,
    /// A truth value (-1/0 in MotionBASIC, ON/OFF in PowerTools): a condition on it may jump
    /// without computing it.
    pub truth: bool,
    /// Where it is.
    pub span: Span,
}

/// The operators, with their dialect's meaning.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Op {
    /// `+`.
    Add,
    /// `-`.
    Sub,
    /// `*`.
    Mul,
    /// `/`.
    Div,
    /// `^`.
    Pow,
    /// PowerTools `MOD`: the remainder with the sign of the left operand.
    Mod,
    /// MotionBASIC `MOD`: both operands rounded to integers first.
    BasicMod,
    /// MotionBASIC `\`.
    IntDiv,
    /// `AND` of ON/OFF values.
    And,
    /// `OR` of ON/OFF values.
    Or,
    /// `XOR` of ON/OFF values.
    Xor,
    /// `AND` bitwise on integers.
    BitAnd,
    /// `OR` bitwise on integers.
    BitOr,
    /// `XOR` bitwise on integers.
    BitXor,
    /// A comparison.
    Cmp(Cmp),
}

/// Comparison operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum Cmp {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

impl Cmp {
    /// Compare two values.
    #[inline(always)]
    pub fn test(self, a: f64, b: f64) -> bool {
        self.test_ord(&a, &b)
    }

    /// Compare two values of any ordered kind (numbers, a string's bytes).
    #[inline(always)]
    pub fn test_ord<T: PartialOrd + ?Sized>(self, a: &T, b: &T) -> bool {
        match self {
            Cmp::Eq => a == b,
            Cmp::Ne => a != b,
            Cmp::Lt => a < b,
            Cmp::Le => a <= b,
            Cmp::Gt => a > b,
            Cmp::Ge => a >= b,
        }
    }

    /// As written.
    pub fn symbol(self) -> &'static str {
        match self {
            Cmp::Eq => "=",
            Cmp::Ne => "<>",
            Cmp::Lt => "<",
            Cmp::Le => "<=",
            Cmp::Gt => ">",
            Cmp::Ge => ">=",
        }
    }
}

/// The kinds of checked expression.
#[derive(Debug, Clone, PartialEq)]
pub enum ExprKind {
    /// A number.
    Const(f64),
    /// ON/OFF, TRUE/FALSE, with the number it is in its dialect (true: 1, or MotionBASIC's -1).
    Bool {
        /// True or false.
        value: bool,
        /// As a number.
        number: f64,
    },
    /// A string literal.
    Str(String),
    /// A member or variable read. `negate`: a bit read as MotionBASIC's true, -1.
    Read {
        /// What is read.
        target: Resolved,
        /// Read as -1/0 rather than 1/0.
        negate: bool,
    },
    /// `-x`.
    Neg(Box<Expr>),
    /// Logical `NOT` of an ON/OFF value.
    Not(Box<Expr>),
    /// Bitwise `NOT` of an integer.
    BitNot(Box<Expr>),
    /// `a op b`; `negate` turns a comparison's 1 into MotionBASIC's -1.
    Binary {
        /// The operator.
        op: Op,
        /// Left operand.
        a: Box<Expr>,
        /// Right operand.
        b: Box<Expr>,
        /// Turn the comparison's 1/0 into -1/0.
        negate: bool,
    },
    /// A math function.
    Call(Func, Vec<Expr>),
    /// A kernel function; `negate`: its OK read as MotionBASIC's -1.
    Kernel {
        /// The function.
        func: KernelFunc,
        /// Its arguments.
        args: Vec<Expr>,
        /// Its truth result read as -1/0.
        negate: bool,
    },
    /// A controller variable of the DSP axes in `axes` (`POS.ASEN@(web~)`): member index
    /// `member` of `Axis`; `truth`: a bit, -1 when it holds on every axis.
    AxisRead {
        /// The `Axis` member.
        member: u8,
        /// Read as a truth value over the set.
        truth: bool,
        /// The axes.
        axes: Box<Expr>,
    },
    /// An axis set `{…}`: its items are axis numbers or sets.
    AxisSet(Vec<Expr>),
    /// `( x )`.
    Paren(Box<Expr>),
    /// An array element read.
    Element(Box<Element>),
    /// A string function (MotionBASIC); `LEN`, `ASC`, `VAL`, `INSTR` give numbers.
    Text(TextFunc, Vec<Expr>),
    /// `RND` or `RND(x)`: the next random number (x < 0 seeds first; x = 0 repeats the last).
    Rnd(Option<Box<Expr>>),
    /// `TIMER`: the simulated seconds since the run started.
    Timer,
}

/// An array element: the array's first element (its storage starts there), its bounds and
/// the subscripts.
#[derive(Debug, Clone, PartialEq)]
pub struct Element {
    /// Element 0 of the array.
    pub base: Resolved,
    /// The upper bound of each subscript.
    pub bounds: Vec<u32>,
    /// The lowest subscript (0, or 1 under `OPTION BASE 1`); storage starts at 0 either way.
    pub lower: u32,
    /// The subscripts, one per bound.
    pub subs: Vec<Expr>,
    /// A string array.
    pub text: bool,
}

/// Where a value is stored.
#[derive(Debug, Clone, PartialEq)]
pub enum Place {
    /// A variable or member.
    Var(Resolved),
    /// An array element.
    Element(Element),
}

/// One constant of a `DATA` statement.
#[derive(Debug, Clone, PartialEq)]
pub struct DataConst {
    /// As written (a quoted item without its quotes).
    pub text: String,
    /// Its value when it reads as a number (a quoted item never does).
    pub number: Option<f64>,
    /// Where it is.
    pub span: Span,
}

/// A checked statement.
#[derive(Debug, Clone, PartialEq)]
pub struct Stmt {
    /// What it does.
    pub kind: StmtKind,
    /// The span of its first line.
    pub span: Span,
}

/// The kinds of checked statement.
#[derive(Debug, Clone, PartialEq)]
pub enum StmtKind {
    /// `target = value`.
    Assign {
        /// Where it goes.
        target: Resolved,
        /// The value.
        value: Expr,
    },
    /// An action run: bare, or assigned ON (`when` None), or assigned a condition (run when it
    /// is ON).
    Act {
        /// The action.
        target: Resolved,
        /// Where a motion starts.
        start: StartRef,
        /// The profile it runs on.
        profile: u8,
        /// Run only when this is ON.
        when: Option<Expr>,
    },
    /// An action assigned OFF: nothing happens.
    Nothing,
    /// A dwell on profile 0.
    Dwell {
        /// Seconds or master units.
        length: Expr,
        /// Which.
        domain: Domain,
        /// `Using Last`: it starts where the previous motion on profile 0 ended.
        last: bool,
    },
    /// `Wait For Time s`.
    WaitTime(Expr),
    /// `Wait For c`.
    WaitFor(Expr),
    /// `If … Else … Endif`.
    If {
        /// The condition.
        cond: Expr,
        /// Run when it holds.
        then_body: Vec<Stmt>,
        /// Run when it does not.
        else_body: Option<Vec<Stmt>>,
    },
    /// `Do While … Loop`, `WHILE … WEND`.
    While {
        /// The condition.
        cond: Expr,
        /// The body.
        body: Vec<Stmt>,
    },
    /// `For v = a To b Step s … Next`.
    For {
        /// The counter.
        var: Resolved,
        /// First value.
        from: Expr,
        /// Limit.
        to: Expr,
        /// Step (1 when absent).
        step: Option<Expr>,
        /// The body.
        body: Vec<Stmt>,
    },
    /// `Call Program.N`.
    Call(u32),
    /// `label:` (its key: the name in lower case).
    Label(String),
    /// `Goto label`.
    Goto(String),
    /// `GOSUB label`.
    Gosub(String),
    /// `RETURN`.
    Return,
    /// `End`.
    End,
    /// A controller variable written on every axis of a set (`SENS.MODE@(web~) = "RRRGN"`).
    AxisWrite {
        /// The `Axis` member.
        member: u8,
        /// What the write does.
        hook: Hook,
        /// The axes.
        axes: Expr,
        /// The value.
        value: Expr,
    },
    /// `PRINT`: the items; the line ends unless the last item is a separator.
    Print(Vec<PrintItem>),
    /// `PRINT USING`: the format, the values, and whether the line ends (no `;` or `,` last).
    PrintUsing {
        /// The format string.
        format: Expr,
        /// The values, in order.
        values: Vec<Expr>,
        /// The line ends after them.
        newline: bool,
    },
    /// A store into an array element (MotionBASIC).
    SetElement {
        /// The element.
        place: Element,
        /// The value.
        value: Expr,
    },
    /// `DATA`: its constants, which `READ` takes in program order.
    Data(Vec<DataConst>),
    /// `READ`: the next constants into these places, in order.
    Read(Vec<Place>),
    /// `RESTORE [label]`: the next `READ` takes the first constant at or after the label (the
    /// label's key), or the program's first.
    Restore(Option<String>),
    /// `SWAP a, b` (same type).
    Swap(Place, Place),
    /// `MID$(v$, start[, n]) = y$`: the characters of the string place from `start` replaced by
    /// those of `value`, the place's subscripts evaluated once.
    MidSet {
        /// The string variable or element changed.
        place: Place,
        /// Where the replacement starts (from 1).
        start: Expr,
        /// At most this many characters replaced.
        count: Option<Expr>,
        /// The replacement.
        value: Expr,
    },
    /// `RANDOMIZE [seed]` (no seed: the scenario's).
    Randomize(Option<Expr>),
    /// A MotionBASIC motion statement (`GEAR`, `MOVE`).
    Motion {
        /// Which, and which operands it has.
        cmd: MotionCmd,
        /// The axes.
        axes: Expr,
        /// Its operands in order (absent ones are 0).
        operands: Vec<Option<Expr>>,
        /// The input an `AFTER` names.
        after: Option<SlotId>,
    },
}

/// How `PRINT` writes a value: as Microsoft BASIC writes its type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PrintHow {
    /// An integer (`%`, `&`): all its digits.
    Integer,
    /// A SINGLE: at most 7 significant digits.
    Single,
    /// A DOUBLE (`#`): at most 16 significant digits.
    Double,
    /// A string.
    Text,
}

/// One checked item of a `PRINT` list.
#[derive(Debug, Clone, PartialEq)]
pub enum PrintItem {
    /// A value, and how to write it.
    Value(Expr, PrintHow),
    /// `;`.
    Semicolon,
    /// `,`: to the next print zone.
    Comma,
}

/// Visit every statement of `stmts` in source order, the statements of `If`, `While` and
/// `For` bodies included (each after the statement that holds it).
pub fn each_stmt<'a>(stmts: &'a [Stmt], f: &mut impl FnMut(&'a Stmt)) {
    for s in stmts {
        f(s);
        match &s.kind {
            StmtKind::If {
                then_body,
                else_body,
                ..
            } => {
                each_stmt(then_body, f);
                each_stmt(else_body.as_deref().unwrap_or_default(), f);
            }
            StmtKind::While { body, .. } | StmtKind::For { body, .. } => each_stmt(body, f),
            _ => {}
        }
    }
}

/// A checked program.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Program {
    /// Its statements.
    pub body: Vec<Stmt>,
}
