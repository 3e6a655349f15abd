//! The abstract syntax tree shared by both dialects. Every node carries its source span.

use crate::span::Span;

pub use crate::registry::name::{Name, Segment};

/// Unary operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnOp {
    /// `-x`
    Neg,
    /// `NOT x`
    Not,
}

/// Binary operators, in BASIC precedence order from lowest (the comparisons share a level,
/// as do `+ -` and `* /`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    /// `XOR`
    Xor,
    /// `OR`
    Or,
    /// `AND`
    And,
    /// `=`
    Eq,
    /// `<>`
    Ne,
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/`
    Div,
    /// `MOD`
    Mod,
    /// `^`
    Pow,
    /// `\` (MotionBASIC integer division).
    IntDiv,
}

impl BinOp {
    /// The operator as written in source.
    pub fn symbol(self) -> &'static str {
        match self {
            BinOp::Or => "OR",
            BinOp::Xor => "XOR",
            BinOp::And => "AND",
            BinOp::Eq => "=",
            BinOp::Ne => "<>",
            BinOp::Lt => "<",
            BinOp::Le => "<=",
            BinOp::Gt => ">",
            BinOp::Ge => ">=",
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Mul => "*",
            BinOp::Div => "/",
            BinOp::Mod => "MOD",
            BinOp::Pow => "^",
            BinOp::IntDiv => "\\",
        }
    }
}

/// An expression.
#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    /// What it is.
    pub kind: ExprKind,
    /// Where it is.
    pub span: Span,
}

/// The kinds of expression.
#[derive(Debug, Clone, PartialEq)]
pub enum ExprKind {
    /// A numeric literal and how it is written.
    Number(f64, NumForm),
    /// ON/TRUE/… or OFF/FALSE/….
    Bool(bool),
    /// A reference to an object member, variable or bit.
    Name(Name),
    /// `-x`, `NOT x`.
    Unary(UnOp, Box<Expr>),
    /// `a op b`.
    Binary(BinOp, Box<Expr>, Box<Expr>),
    /// A function call such as `ABS(x)`.
    Call(Segment, Vec<Expr>),
    /// `( x )`, kept so diagnostics can point at the parentheses.
    Paren(Box<Expr>),
    /// A string literal (MotionBASIC).
    Str(String),
    /// An axis set `{1}`, `{web~, knife~}` (MotionBASIC).
    AxisSet(Vec<Expr>),
}

/// How a numeric literal is written, which gives its type in Microsoft BASIC.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NumForm {
    /// Digits only (`1000`): an INTEGER within 16 bits, a LONG beyond.
    Whole,
    /// With a point or an `E` exponent (`2.0`, `1E7`): a SINGLE, a DOUBLE beyond 7 digits.
    Real,
    /// With `%`, or `&H`/`&O` within 16 bits (`7%`, `&HFF`): an INTEGER.
    Integer,
    /// With `&`, or `&H`/`&O` beyond 16 bits (`1000&`, `&HFFFF&`): a LONG.
    Long,
    /// With `!` (`2!`): a SINGLE.
    Single,
    /// With `#` or a `D` exponent (`7#`, `1.5D3`): a DOUBLE.
    Double,
}

/// The forms of the MotionBASIC `GEAR` statement.
#[derive(Debug, Clone, PartialEq)]
pub enum GearForm {
    /// `GEAR axis AT out TO in [IN pacer_dist] [AFTER input]`.
    At {
        out: Expr,
        inn: Expr,
        pacer: Option<Expr>,
        after: Option<Expr>,
    },
    /// `GEAR axis FOR dist IN pacer_dist`: superimposed on the running gear.
    For { dist: Expr, pacer: Expr },
}

/// The forms of the MotionBASIC `MOVE` statement.
#[derive(Debug, Clone, PartialEq)]
pub enum MoveForm {
    /// `MOVE axis AT speed [IN time]`: run at a speed (RPM), reaching it in `time` ms.
    At { speed: Expr, time: Option<Expr> },
    /// `MOVE axis TO position [AT speed] [IN time]` / `MOVE axis FOR distance …`.
    Position {
        relative: bool,
        target: Expr,
        speed: Option<Expr>,
        time: Option<Expr>,
    },
}

/// What an initiate starts from.
#[derive(Debug, Clone, PartialEq)]
pub enum Using {
    /// `Using Last`: where the previous motion ended on the internal timeline.
    Last(Span),
    /// `Using Capture.N`: from a capture object's latched data.
    Capture(Name),
}

/// A statement. Block statements own their bodies.
#[derive(Debug, Clone, PartialEq)]
pub struct Stmt {
    /// What it is.
    pub kind: StmtKind,
    /// The span of its first line.
    pub span: Span,
}

/// The kinds of statement.
#[derive(Debug, Clone, PartialEq)]
pub enum StmtKind {
    /// `target = value`.
    Assign { target: Name, value: Expr },
    /// A bare action, e.g. `Queue.0.QueueRemove`, `Index.0.Initiate Using Capture.1 On Profile.1`.
    Action {
        target: Name,
        using: Option<Using>,
        profile: Option<Name>,
    },
    /// `Dwell For Time s [Using Last]` (the span of `Using Last` when written).
    DwellTime(Expr, Option<Span>),
    /// `Dwell For Master Dist d [Using Last]`.
    DwellMaster(Expr, Option<Span>),
    /// `Wait For Time s`.
    WaitTime(Expr),
    /// `Wait For expr`.
    WaitFor(Expr),
    /// `If c Then … [Else …] Endif`.
    If {
        cond: Expr,
        then_body: Vec<Stmt>,
        else_body: Option<Vec<Stmt>>,
    },
    /// `Do While c … Loop`.
    DoWhile { cond: Expr, body: Vec<Stmt> },
    /// `For v = a To b [Step s] … Next [v]`.
    For {
        var: Name,
        from: Expr,
        to: Expr,
        step: Option<Expr>,
        body: Vec<Stmt>,
    },
    /// `Call Program.N`: runs another program on this task and comes back.
    Call(Name),
    /// `label:`.
    Label(Segment),
    /// `Goto label` / `Jump label`.
    Goto(Segment),
    /// `EXIT FOR` / `EXIT DO` (MotionBASIC, as QuickBASIC writes them; `for_`: which). Made a
    /// `Goto` to the end of the innermost such loop when the blocks are assembled
    /// (`syntax::blocks`): no later pass sees it.
    Exit { for_: bool },
    /// `End`.
    End,
    /// `NAME(args) = value` / `NAME{axes} = value`: a MotionBASIC controller variable.
    SetCall {
        target: Segment,
        args: Vec<Expr>,
        value: Expr,
    },
    /// `GOSUB label`, or a bare label name (MotionBASIC).
    Gosub(Segment),
    /// `RETURN`.
    Return,
    /// `GEAR axis …`.
    Gear { axis: Expr, form: GearForm },
    /// `MOVE axis …`.
    Move { axis: Expr, form: MoveForm },
    /// `PRINT items` (MotionBASIC).
    Print(Vec<PrintItem>),
    /// `PRINT USING format; items` (MotionBASIC).
    PrintUsing(Expr, Vec<PrintItem>),
    /// `DIM A(10), B$(2, 3)` (MotionBASIC): each array and its upper bounds.
    Dim(Vec<(Segment, Vec<Expr>)>),
    /// `DATA 1, -2.5, "TEXT", WORD` (MotionBASIC).
    Data(Vec<DataItem>),
    /// `READ A, B$(I)` (MotionBASIC).
    Read(Vec<Place>),
    /// `RESTORE [label]` (MotionBASIC).
    Restore(Option<Segment>),
    /// `SWAP a, b` (MotionBASIC).
    Swap(Place, Place),
    /// `RANDOMIZE [seed]` (MotionBASIC).
    Randomize(Option<Expr>),
    /// `DEFINT I-N, X` and the like (MotionBASIC): the suffix unsuffixed names starting with
    /// the letters get (`%`, `&`, `!`, `#`, `$`), and the letter ranges as written. The syntax
    /// pass that applies it (`syntax::deftype`) leaves the statement in place, with nothing
    /// left to do.
    DefType {
        /// The type suffix.
        suffix: char,
        /// Each letter or range `I-N`.
        ranges: Vec<(Segment, Option<Segment>)>,
    },
    /// `OPTION BASE n` (MotionBASIC): the lowest subscript of the program's arrays, as
    /// written (the checker takes a literal 0 or 1 only).
    OptionBase(Expr),
    /// `CONST name = value, …` (MotionBASIC, as QuickBASIC writes it). Made assignments once
    /// checked (`syntax::consts`): no later pass sees it.
    Const(Vec<(Name, Expr)>),
}

/// One item of a `DATA` statement.
#[derive(Debug, Clone, PartialEq)]
pub struct DataItem {
    /// The text: a quoted string's contents, or an unquoted item trimmed.
    pub text: String,
    /// Written in quotes (always a string).
    pub quoted: bool,
    /// Where it is.
    pub span: Span,
}

/// A place a value can be stored: a variable or an array element.
#[derive(Debug, Clone, PartialEq)]
pub enum Place {
    /// A variable.
    Var(Name),
    /// `A(i, j)`: the array, its subscripts, and the whole element's span.
    Element(Segment, Vec<Expr>, Span),
}

impl Place {
    /// Where it is written.
    pub fn span(&self) -> Span {
        match self {
            Place::Var(n) => n.span,
            Place::Element(_, _, span) => *span,
        }
    }
}

/// One item of a `PRINT` list.
#[derive(Debug, Clone, PartialEq)]
pub enum PrintItem {
    /// A value to print.
    Expr(Expr),
    /// `;`: the next item follows at once.
    Semicolon,
    /// `,`: the next item starts at the next print zone.
    Comma,
}

/// Every label of `body`, nested blocks included, in source order.
pub fn labels(body: &[Stmt]) -> Vec<&Segment> {
    let mut out = Vec::new();
    fn walk<'a>(body: &'a [Stmt], out: &mut Vec<&'a Segment>) {
        for s in body {
            match &s.kind {
                StmtKind::Label(seg) => out.push(seg),
                StmtKind::If {
                    then_body,
                    else_body,
                    ..
                } => {
                    walk(then_body, out);
                    if let Some(e) = else_body {
                        walk(e, out);
                    }
                }
                StmtKind::DoWhile { body, .. } | StmtKind::For { body, .. } => walk(body, out),
                _ => {}
            }
        }
    }
    walk(body, &mut out);
    out
}

/// A parsed program file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ProgramAst {
    /// The top-level statements.
    pub body: Vec<Stmt>,
}
