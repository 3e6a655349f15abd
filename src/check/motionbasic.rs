//! The MotionBASIC dialect's rules: variables typed by their suffix and declared by use,
//! controller variables (`POS.ASEN@(axis)`) as members of the DSP axis objects, truth values
//! as numbers (-1 is true), long-integer arithmetic that overflows at 32 bits, subroutines by
//! label, the motion statements, and the lint for a variable read but never assigned.

use super::functions;
use super::typed::{self, ExprKind as K, Op, StmtKind as T, Ty};
use super::walk::{not_here, unknown_label, Context, Rules, Want};
use crate::devices::command::{GearAfter, MotionCmd};
use crate::devices::orion::dsp::Sensor;
use crate::diag::{nearest, Problem};
use crate::registry::catalog::AXIS_TYPE;
use crate::registry::{
    Access, ArrayShape, BasicVar, Kind, Registry, Resolved, SlotName, ValueType,
};
use crate::span::Span;
use crate::syntax::ast::{
    BinOp, Expr, ExprKind, GearForm, MoveForm, Name, NumForm, Place, PrintItem, ProgramAst,
    Segment, Stmt, StmtKind, UnOp,
};
use crate::syntax::Dialect;
use indexmap::{IndexMap, IndexSet};
use std::sync::Arc;

/// What a MotionBASIC value is: a number (long integer or real; truth values are numbers), an
/// axis set (`{1}`, `web~`) or a string.
pub type BasicTy = Ty;

/// A MotionBASIC value type as messages name it.
fn word(t: Ty) -> &'static str {
    match t {
        Ty::Num | Ty::Bool => "a number",
        Ty::Axis => "an axis set",
        Ty::Str => "a string",
    }
}

/// The storage type of a variable, from its suffix: `&`/`%` long integer, `~` axis set,
/// `$` string, none/`!`/`#` real. `None` for a controller name (`@`).
pub fn var_type(name: &str) -> Option<(ValueType, BasicTy)> {
    match name.chars().last()? {
        '@' => None,
        '&' | '%' => Some((ValueType::Fixed(0), Ty::Num)),
        '~' => Some((ValueType::Integer, Ty::Axis)),
        '$' => Some((ValueType::Integer, Ty::Str)),
        _ => Some((ValueType::Real, Ty::Num)),
    }
}

/// A controller variable and the DSP axis member it names.
#[derive(Debug, Clone, Copy)]
pub struct Controller {
    /// MotionBASIC name without `@`.
    pub name: &'static str,
    /// The `Axis` member.
    pub member: &'static str,
    /// Programs may assign it.
    pub writable: bool,
    /// Type of its value.
    pub ty: BasicTy,
}

const fn ctl(name: &'static str, member: &'static str, writable: bool, ty: BasicTy) -> Controller {
    Controller {
        name,
        member,
        writable,
        ty,
    }
}

/// Every controller variable pacer knows.
pub const CONTROLLERS: &[Controller] = &[
    ctl("POS", "Position", false, Ty::Num),
    ctl("VEL", "Velocity", false, Ty::Num),
    ctl("RATIO", "Ratio", false, Ty::Num),
    ctl("DSP.DONE", "DspDone", false, Ty::Num),
    ctl("ZREF", "Zref", true, Ty::Num),
    ctl("ASEN", "Asen", true, Ty::Num),
    ctl("BSEN", "Bsen", true, Ty::Num),
    ctl("POS.ZREF", "PosZref", false, Ty::Num),
    ctl("POS.ASEN", "PosAsen", false, Ty::Num),
    ctl("POS.BSEN", "PosBsen", false, Ty::Num),
    ctl("POS.MOD", "PosMod", true, Ty::Num),
    ctl("PLS.MOD", "PlsMod", true, Ty::Num),
    ctl("PLS1.LOW", "Pls1Low", true, Ty::Num),
    ctl("PLS1.HIGH", "Pls1High", true, Ty::Num),
    ctl("PLS2.LOW", "Pls2Low", true, Ty::Num),
    ctl("PLS2.HIGH", "Pls2High", true, Ty::Num),
    ctl("PLS3.LOW", "Pls3Low", true, Ty::Num),
    ctl("PLS3.HIGH", "Pls3High", true, Ty::Num),
    ctl("SENS.MODE", "SensMode", true, Ty::Str),
];

/// The controller variable `name` names, written with or without its `@`.
pub fn controller(name: &str) -> Option<&'static Controller> {
    let bare = name.strip_suffix('@').unwrap_or(name);
    CONTROLLERS
        .iter()
        .find(|c| c.name.eq_ignore_ascii_case(bare))
}

/// A name in a MotionBASIC program: an object member when it resolves as one
/// (`Queue.0.QueueEmpty`), else a MotionBASIC variable.
pub fn resolve(registry: &Registry, name: &Name) -> Result<Resolved, Problem> {
    let text = name.text();
    if text.ends_with('@') {
        let help = match controller(&text) {
            Some(c) => format!("give its axis: `{}@(knife~)`", c.name),
            None => "controller variables take an axis in ( ) or { }".to_string(),
        };
        return Err(Problem::error(
            "pacer::check::controller_axis",
            name.span,
            format!("{text} is a controller variable: it needs an axis"),
            "no axis given",
        )
        .with_help(help));
    }
    // Microsoft BASIC's OFF is a keyword, never a value: read as a variable it would silently
    // be 0. (ON is a token of its own, `ON n GOTO`; the parser says the same of it.)
    if name.segments.len() == 1 && text.eq_ignore_ascii_case("OFF") {
        return Err(Problem::error(
            "pacer::check::on_off",
            name.span,
            format!("`{text}` is a keyword in MotionBASIC, not a value"),
            "not a value",
        )
        .with_help("MotionBASIC writes truth as TRUE (-1) and FALSE (0): write FALSE"));
    }
    if crate::registry::catalog::find_type(&name.segments[0].text).is_some() {
        if let Ok(r) = registry.resolve(name) {
            return Ok(r);
        }
    }
    let vars = registry.of(Kind::BasicVar);
    let instance = match vars.names.get(&text.to_ascii_lowercase()) {
        Some(&i) => Some(i),
        None => match registry.basic_element(&text) {
            Some(Ok(i)) => Some(i),
            Some(Err(message)) => {
                return Err(Problem::error(
                    SUBSCRIPT,
                    name.span,
                    format!("Subscript out of range: {message}"),
                    "no such element",
                ))
            }
            None => None,
        },
    };
    match instance {
        Some(i) => {
            let slot = vars.slot(i, 0, false);
            let info = &registry.slots[slot as usize];
            Ok(Resolved {
                slot,
                ty: info.ty,
                access: Access::ReadWrite,
                hook: crate::registry::Hook::Store,
                kind: Kind::BasicVar,
                instance: i,
                name: info.name.text().into_owned(),
            })
        }
        None => registry.resolve(name),
    }
}

/// The variables of MotionBASIC programs, in order of first appearance, with their types, and
/// the ones assigned somewhere (for the read-never-assigned lint).
#[derive(Debug, Default)]
pub struct Variables {
    /// Name (upper-case) → spelling at first use (as the trace shows it) and storage type.
    pub all: IndexMap<String, (String, ValueType)>,
    /// Names assigned (or used as a FOR variable) somewhere; an array as `NAME()`.
    pub assigned: IndexSet<String>,
    /// Arrays by name (upper-case, with its suffix), in order of first appearance.
    pub arrays: IndexMap<String, Array>,
    /// The lowest subscript the program being collected gives its arrays (its OPTION BASE).
    base: u32,
    /// The program being collected may still say OPTION BASE: no array and no OPTION BASE
    /// yet (the checker refuses a later one).
    base_open: bool,
}

/// Most subscripts an array may have.
pub const MAX_DIMENSIONS: usize = 8;

/// Largest upper bound of a subscript (Microsoft BASIC's).
pub const MAX_BOUND: u32 = 32767;

/// The code of a subscript outside its array's bounds, written in a program or in a name
/// (`F&(11)` of `DIM F&(10)`).
pub const SUBSCRIPT: &str = "pacer::check::subscript_range";

/// Most array elements all the programs of a machine may have: each element is a traced
/// variable of the machine, and a bound keeps a mistyped `DIM` from taking the memory.
pub const MAX_ELEMENTS: usize = 65536;

/// An array of MotionBASIC programs.
#[derive(Debug, Clone)]
pub struct Array {
    /// The name as first written.
    pub written: String,
    /// The storage type of its elements.
    pub ty: ValueType,
    /// The upper bound of each subscript (each from 0); `None` when its `DIM` cannot be
    /// allocated (the checker says why).
    pub bounds: Option<Vec<u32>>,
    /// Dimensioned by a `DIM` (not implicitly, by use, as 0 to 10).
    pub declared: bool,
    /// The lowest subscript: 0, or 1 when the program that dimensions it (or first uses it,
    /// without DIM) says `OPTION BASE 1`. Storage still starts at subscript 0 (element 0 of a
    /// base-1 array is there, unused), so elements keep their names.
    pub lower: u32,
}

impl Array {
    /// Its number of elements.
    pub fn len(&self) -> usize {
        self.bounds
            .as_ref()
            .map_or(0, |b| b.iter().map(|&n| n as usize + 1).product())
    }

    /// Whether it has no element (its DIM failed).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The value of a constant expression (numbers and arithmetic on them), as `DIM` bounds are.
pub fn constant(e: &Expr) -> Option<f64> {
    match &e.kind {
        ExprKind::Number(v, _) => Some(*v),
        ExprKind::Paren(a) => constant(a),
        ExprKind::Unary(UnOp::Neg, a) => constant(a).map(|v| -v),
        ExprKind::Binary(op, a, b) => {
            let (a, b) = (constant(a)?, constant(b)?);
            match op {
                BinOp::Add => Some(a + b),
                BinOp::Sub => Some(a - b),
                BinOp::Mul => Some(a * b),
                BinOp::Div if b != 0.0 => Some(a / b),
                BinOp::IntDiv if b.round_ties_even() != 0.0 => {
                    Some((a.round_ties_even() / b.round_ties_even()).trunc())
                }
                _ => None,
            }
        }
        _ => None,
    }
}

/// The lowest subscript `OPTION BASE e` gives: `e` is the number 0 or 1 as written.
pub fn option_base(e: &Expr) -> Option<u32> {
    match e.kind {
        ExprKind::Number(0.0, NumForm::Whole) => Some(0),
        ExprKind::Number(1.0, NumForm::Whole) => Some(1),
        _ => None,
    }
}

/// `MID$(…) = …` is the MID$ statement.
fn is_mid(text: &str) -> bool {
    super::text::find(text).is_some_and(|d| d.func == super::text::TextFunc::Mid)
}

/// `NAME(…)` names an array element unless NAME is a function or a controller variable.
pub fn array_call(text: &str) -> bool {
    !text.ends_with('@')
        && functions::find(text).is_none()
        && functions::find_kernel(text).is_none()
        && super::text::find(text).is_none()
        && controller(text).is_none()
        && builtin(text).is_none()
}

/// A value of the machine read by a bare name: `RND` (the next random number) or `TIMER`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Builtin {
    /// `RND`.
    Rnd,
    /// `TIMER`: the simulated seconds since the run started.
    Timer,
}

/// The builtin `text` names, if any.
pub fn builtin(text: &str) -> Option<Builtin> {
    if text.eq_ignore_ascii_case("RND") {
        Some(Builtin::Rnd)
    } else if text.eq_ignore_ascii_case("TIMER") {
        Some(Builtin::Timer)
    } else {
        None
    }
}

/// The bounds a `DIM` gives, each a whole number from 0 to [`MAX_BOUND`]; Err with the
/// bound at fault and why.
pub fn dim_bounds(bounds: &[Expr]) -> Result<Vec<u32>, (Span, String)> {
    if bounds.len() > MAX_DIMENSIONS {
        let span = bounds[MAX_DIMENSIONS].span;
        return Err((
            span,
            format!("an array has at most {MAX_DIMENSIONS} subscripts"),
        ));
    }
    bounds
        .iter()
        .map(|b| match constant(b) {
            Some(v) if v.round_ties_even() >= 0.0 && v.round_ties_even() <= f64::from(MAX_BOUND) => {
                Ok(v.round_ties_even() as u32)
            }
            Some(v) => Err((
                b.span,
                format!("a subscript's upper bound is a whole number from 0 to {MAX_BOUND}, not {v}"),
            )),
            None => Err((
                b.span,
                "pacer sizes arrays before the run: a DIM bound is a number (or arithmetic on numbers)"
                    .to_string(),
            )),
        })
        .collect()
}

impl Variables {
    /// The variables and arrays a machine's registry already holds (its MotionBASIC variables
    /// and array elements by name, as the registry lists them), all taken as assigned: what a
    /// line typed at the REPL may use. `lower`: the lowest subscript of the arrays that do not
    /// start at 0 (the registry holds their elements from 0).
    pub fn known<'a>(
        names: impl Iterator<Item = (&'a SlotName, ValueType)>,
        lower: &IndexMap<String, u32>,
    ) -> Variables {
        let mut vars = Variables::default();
        for (name, ty) in names {
            let name = match name {
                SlotName::Text(name) => name.as_str(),
                SlotName::Element { array, index } => {
                    // Its shape is the array's: its first element stands for all.
                    if *index != 0 {
                        continue;
                    }
                    let key = array.written.to_ascii_uppercase();
                    vars.assigned.insert(format!("{key}()"));
                    let lowest = lower.get(&key).copied().unwrap_or(0);
                    vars.arrays.entry(key).or_insert_with(|| Array {
                        written: array.written.clone(),
                        ty,
                        bounds: Some(array.bounds.clone()),
                        declared: true,
                        lower: lowest,
                    });
                    continue;
                }
            };
            let key = name.to_ascii_uppercase();
            let Some((base, subs)) = name.split_once('(') else {
                vars.all.insert(key.clone(), (name.to_string(), ty));
                vars.assigned.insert(key);
                continue;
            };
            let subs: Vec<u32> = subs
                .trim_end_matches(')')
                .split(',')
                .map(|p| p.trim().parse().unwrap_or(0))
                .collect();
            let base_key = base.to_ascii_uppercase();
            vars.assigned.insert(format!("{base_key}()"));
            let lowest = lower.get(&base_key).copied().unwrap_or(0);
            let array = vars.arrays.entry(base_key).or_insert_with(|| Array {
                written: base.to_string(),
                ty,
                bounds: Some(vec![0; subs.len()]),
                declared: true,
                lower: lowest,
            });
            if let Some(bounds) = array.bounds.as_mut() {
                for (b, s) in bounds.iter_mut().zip(&subs) {
                    *b = (*b).max(*s);
                }
            }
        }
        vars
    }

    /// Collect the variables `ast` uses. Names that are objects of the machine, labels and
    /// controller names are not variables.
    pub fn collect(&mut self, ast: &ProgramAst) {
        self.base = 0;
        self.base_open = true;
        self.stmts(&ast.body);
    }

    /// The variables for the registry: the scalars, then the arrays (each array's elements are
    /// consecutive slots).
    pub fn list(&self) -> Vec<BasicVar> {
        let mut out: Vec<BasicVar> = self
            .all
            .values()
            .map(|(name, ty)| BasicVar::Scalar(name.clone(), *ty))
            .collect();
        for a in self.arrays.values() {
            if let Some(bounds) = &a.bounds {
                let shape = ArrayShape {
                    written: a.written.clone(),
                    bounds: bounds.clone(),
                };
                out.push(BasicVar::Array(Arc::new(shape), a.ty));
            }
        }
        out
    }

    /// Total elements of the arrays so far.
    fn elements(&self) -> usize {
        self.arrays.values().map(Array::len).sum()
    }

    /// An array named `seg` with `count` subscripts, dimensioned by `dim` when given (else
    /// implicitly, 0 to 10 each); `assigned` when stored into.
    fn note_array(&mut self, seg: &Segment, count: usize, dim: Option<&[Expr]>, assigned: bool) {
        self.base_open = false;
        let key = seg.text.to_ascii_uppercase();
        let Some((ty, _)) = var_type(&key) else {
            return;
        };
        if assigned {
            self.assigned.insert(format!("{key}()"));
        }
        let declared = self.arrays.get(&key).is_some_and(|a| a.declared);
        if self.arrays.contains_key(&key) && (declared || dim.is_none()) {
            return;
        }
        let bounds = match dim {
            Some(b) => dim_bounds(b).ok(),
            None => Some(vec![10; count.clamp(1, MAX_DIMENSIONS)]),
        };
        let mut array = Array {
            written: seg.text.clone(),
            ty,
            bounds,
            declared: dim.is_some(),
            lower: self.base,
        };
        let others = self.elements() - self.arrays.get(&key).map_or(0, Array::len);
        if others + array.len() > MAX_ELEMENTS {
            array.bounds = None;
        }
        self.arrays.insert(key, array);
    }

    fn place(&mut self, p: &Place) {
        match p {
            Place::Var(n) => self.note(n, true),
            Place::Element(seg, args, _) => {
                self.note_array(seg, args.len(), None, true);
                args.iter().for_each(|a| self.expr(a));
            }
        }
    }

    fn note(&mut self, n: &Name, assigned: bool) {
        // `BELT.SPEED` stays a variable: a belt is always written with its number.
        let object = match crate::registry::catalog::find_type(&n.segments[0].text) {
            Some(def) if def.kind == Kind::Belt => n
                .segments
                .get(1)
                .is_some_and(|s| !s.text.is_empty() && s.text.bytes().all(|b| b.is_ascii_digit())),
            Some(_) => n.segments.len() > 1,
            None => false,
        };
        if object {
            return;
        }
        let written = n.text();
        let text = written.to_ascii_uppercase();
        if builtin(&text).is_some() {
            return;
        }
        let Some((ty, _)) = var_type(&text) else {
            return;
        };
        self.all.entry(text.clone()).or_insert((written, ty));
        if assigned {
            self.assigned.insert(text);
        }
    }

    fn stmts(&mut self, body: &[Stmt]) {
        for s in body {
            match &s.kind {
                StmtKind::Assign { target, value } => {
                    self.note(target, true);
                    self.expr(value);
                }
                StmtKind::SetCall {
                    target,
                    args,
                    value,
                } => {
                    if array_call(&target.text) {
                        self.note_array(target, args.len(), None, true);
                    }
                    args.iter().for_each(|a| self.expr(a));
                    self.expr(value);
                }
                StmtKind::Dim(arrays) => {
                    for (seg, bounds) in arrays {
                        self.note_array(seg, bounds.len(), Some(bounds), false);
                    }
                }
                StmtKind::Read(places) => places.iter().for_each(|p| self.place(p)),
                StmtKind::Swap(a, b) => {
                    self.place(a);
                    self.place(b);
                }
                StmtKind::Randomize(Some(e)) => self.expr(e),
                StmtKind::OptionBase(e) => {
                    if let (true, Some(b)) = (self.base_open, option_base(e)) {
                        self.base = b;
                    }
                    self.base_open = false;
                }
                StmtKind::If {
                    cond,
                    then_body,
                    else_body,
                } => {
                    self.expr(cond);
                    self.stmts(then_body);
                    if let Some(e) = else_body {
                        self.stmts(e);
                    }
                }
                StmtKind::DoWhile { cond, body } => {
                    self.expr(cond);
                    self.stmts(body);
                }
                StmtKind::For {
                    var,
                    from,
                    to,
                    step,
                    body,
                } => {
                    self.note(var, true);
                    self.expr(from);
                    self.expr(to);
                    if let Some(s) = step {
                        self.expr(s);
                    }
                    self.stmts(body);
                }
                StmtKind::Gear { axis, form } => {
                    self.expr(axis);
                    match form {
                        GearForm::At {
                            out,
                            inn,
                            pacer,
                            after,
                        } => {
                            self.expr(out);
                            self.expr(inn);
                            // `AFTER ASEN` names a sensor, not a variable.
                            let input = after.as_ref().filter(|a| after_sensor(a).is_none());
                            pacer.iter().chain(input).for_each(|e| self.expr(e));
                        }
                        GearForm::For { dist, pacer } => {
                            self.expr(dist);
                            self.expr(pacer);
                        }
                    }
                }
                StmtKind::Move { axis, form } => {
                    self.expr(axis);
                    match form {
                        MoveForm::At { speed, time } => {
                            self.expr(speed);
                            time.iter().for_each(|e| self.expr(e));
                        }
                        MoveForm::Position {
                            target,
                            speed,
                            time,
                            ..
                        } => {
                            self.expr(target);
                            speed.iter().chain(time.iter()).for_each(|e| self.expr(e));
                        }
                    }
                }
                StmtKind::WaitFor(e)
                | StmtKind::WaitTime(e)
                | StmtKind::DwellTime(e, _)
                | StmtKind::DwellMaster(e, _) => self.expr(e),
                StmtKind::Print(items) => {
                    for item in items {
                        if let PrintItem::Expr(e) = item {
                            self.expr(e);
                        }
                    }
                }
                StmtKind::PrintUsing(format, items) => {
                    self.expr(format);
                    for item in items {
                        if let PrintItem::Expr(e) = item {
                            self.expr(e);
                        }
                    }
                }
                _ => {}
            }
        }
    }

    fn expr(&mut self, e: &Expr) {
        match &e.kind {
            ExprKind::Name(n) => self.note(n, false),
            ExprKind::Unary(_, a) | ExprKind::Paren(a) => self.expr(a),
            ExprKind::Binary(_, a, b) => {
                self.expr(a);
                self.expr(b);
            }
            ExprKind::Call(f, args) => {
                if array_call(&f.text) {
                    self.note_array(f, args.len(), None, false);
                }
                args.iter().for_each(|a| self.expr(a))
            }
            ExprKind::AxisSet(args) => args.iter().for_each(|a| self.expr(a)),
            ExprKind::Number(..) | ExprKind::Bool(_) | ExprKind::Str(_) => {}
        }
    }
}

/// Check a MotionBASIC program against the registry; `vars` holds every MotionBASIC program's
/// variables. Every problem found.
pub fn check(ast: &ProgramAst, registry: &Registry, vars: &Variables) -> Vec<Problem> {
    let machine = super::walk::Machine {
        registry,
        loaded_programs: &[],
        all_programs: true,
    };
    super::walk::check(&mut MotionBasic::new(vars), &machine, ast).1
}

/// The MotionBASIC rules; `vars` holds every MotionBASIC program's variables.
pub struct MotionBasic<'v> {
    vars: &'v Variables,
    /// Variables already reported as never assigned.
    warned: IndexSet<String>,
    /// Arrays already reported as used without DIM.
    implicit: IndexSet<String>,
    /// Arrays this program dimensions.
    dimensioned: IndexSet<String>,
    /// The lowest subscript of the arrays this program dimensions (its OPTION BASE so far).
    base: u32,
    /// Where the program's OPTION BASE is, once seen.
    option_base: Option<Span>,
    /// The program's first array as written, and whether that was its DIM (else a use):
    /// OPTION BASE must come before it.
    first_array: Option<(String, bool)>,
}

impl<'v> MotionBasic<'v> {
    /// The rules for programs whose variables are `vars`.
    pub fn new(vars: &'v Variables) -> MotionBasic<'v> {
        MotionBasic {
            vars,
            warned: IndexSet::new(),
            implicit: IndexSet::new(),
            dimensioned: IndexSet::new(),
            base: 0,
            option_base: None,
            first_array: None,
        }
    }

    /// `e`, which must be of type `ty` (the help line says why).
    fn want(&mut self, cx: &mut Context<'_>, e: &Expr, ty: Ty, why: &str) -> Option<typed::Expr> {
        let t = self.ty(cx, e)?;
        if t.ty != ty {
            cx.push(
                Problem::error(
                    "pacer::check::type",
                    e.span,
                    format!("{} is needed here, not {}", word(ty), word(t.ty)),
                    format!("this is {}", word(t.ty)),
                )
                .with_help(why.to_string()),
            );
            return None;
        }
        Some(t)
    }

    /// The `AFTER` input of a `GEAR`: its slot.
    fn after_input(&mut self, cx: &mut Context<'_>, e: &Expr) -> Option<u32> {
        let latch = match &e.kind {
            ExprKind::Name(n) if n.segments.len() == 1 => {
                let text = n.text().to_ascii_uppercase();
                text.strip_suffix('@')
                    .filter(|t| SENSOR_NAMES.iter().any(|(s, _)| s == t))
                    .map(str::to_string)
            }
            _ => None,
        };
        if let Some(name) = latch {
            cx.push(
                Problem::error(
                    "pacer::check::after",
                    e.span,
                    format!("AFTER names the sensor input `{name}`, not its latch `{name}@`"),
                    "a latch",
                )
                .with_help(format!(
                    "write `AFTER {name}`: the gear starts at the sensor's next edge"
                )),
            );
            return None;
        }
        let mut near = None;
        let found = match &e.kind {
            ExprKind::Name(n) => match cx.registry().resolve(n) {
                Ok(r) => (r.ty.is_bit() && !matches!(r.access, Access::Action | Access::Input))
                    .then_some(r.slot),
                // A lone word is more likely a misspelt sensor than an object of the machine.
                Err(_) if n.segments.len() == 1 => {
                    near = nearest(&n.text(), SENSOR_NAMES.iter().map(|(s, _)| *s));
                    None
                }
                Err(p) => {
                    cx.push(p);
                    return None;
                }
            },
            _ => None,
        };
        if found.is_none() {
            cx.push(
                Problem::error(
                    "pacer::check::after",
                    e.span,
                    "AFTER needs a sensor or an input",
                    "not a sensor or an input",
                )
                .with_help(format!(
                    "{}AFTER takes a sensor of the axis's DSP card (`ZREF`, `ASEN`, `BSEN`) or \
                     an input bit (e.g. `DriveInput.1`)",
                    near.map_or(String::new(), |s| format!("did you mean `{s}`? "))
                )),
            );
        }
        found
    }

    /// The one axis set a controller variable takes.
    fn axis_args(
        &mut self,
        cx: &mut Context<'_>,
        target: &Segment,
        args: &[Expr],
    ) -> Option<typed::Expr> {
        if args.len() != 1 {
            cx.push(Problem::error(
                "pacer::check::arguments",
                target.span,
                format!(
                    "{} takes one axis set, not {} arguments",
                    target.text,
                    args.len()
                ),
                "wrong number of arguments",
            ));
        }
        let mut first = None;
        for (i, a) in args.iter().enumerate() {
            let t = self.want(
                cx,
                a,
                Ty::Axis,
                "controller variables take an axis: `POS.ASEN@(web~)`",
            );
            if i == 0 {
                first = t;
            }
        }
        if args.len() != 1 {
            return None;
        }
        first
    }

    /// The type of an expression, every problem in it recorded.
    fn ty(&mut self, cx: &mut Context<'_>, e: &Expr) -> Option<typed::Expr> {
        let typed = |kind, ty, long, truth| typed::Expr {
            kind,
            ty,
            long,
            int16: false,
            int_const: false,
            truth,
            span: e.span,
        };
        match &e.kind {
            ExprKind::Number(v, _) if !v.is_finite() => {
                cx.push(Problem::error(
                    "pacer::check::number",
                    e.span,
                    "this number is too large to represent",
                    "out of range",
                ));
                None
            }
            ExprKind::Number(v, form @ (NumForm::Integer | NumForm::Long))
                if v.fract() != 0.0
                    || (*form == NumForm::Integer && !(-32768.0..=32767.0).contains(v))
                    || !(f64::from(i32::MIN)..=f64::from(i32::MAX)).contains(v) =>
            {
                let (what, range) = if *form == NumForm::Integer {
                    ("an INTEGER constant (`%`)", "-32768 to 32767")
                } else {
                    ("a LONG constant (`&`)", "-2147483648 to 2147483647")
                };
                cx.push(
                    Problem::error(
                        "pacer::check::number",
                        e.span,
                        format!("Overflow: {what} is a whole number from {range}"),
                        "not such a number",
                    )
                    .with_help("write it without the suffix, or with `!` or `#` for a real"),
                );
                None
            }
            ExprKind::Number(v, form) => {
                let whole = v.fract() == 0.0;
                // Microsoft BASIC's type of the literal: `1000` is an INTEGER, `1000&` a LONG,
                // `1000!` a SINGLE. A literal with a point or exponent but a whole value keeps
                // computing as a long, as before suffixes were read.
                let long = match form {
                    NumForm::Whole | NumForm::Real => whole && v.abs() <= f64::from(i32::MAX),
                    NumForm::Integer | NumForm::Long => true,
                    NumForm::Single | NumForm::Double => false,
                };
                let mut t = typed(K::Const(*v), Ty::Num, long, false);
                t.int_const = match form {
                    NumForm::Whole => whole && v.abs() <= 32767.0,
                    NumForm::Integer => true,
                    _ => false,
                };
                // `7%` is a `%` operand: INTEGER arithmetic on it is done in 16 bits.
                t.int16 = *form == NumForm::Integer;
                Some(t)
            }
            ExprKind::Bool(b) => Some(typed(
                K::Bool {
                    value: *b,
                    number: if *b { -1.0 } else { 0.0 },
                },
                Ty::Num,
                true,
                true,
            )),
            ExprKind::Str(s) => Some(typed(K::Str(s.clone()), Ty::Str, false, false)),
            ExprKind::Paren(a) => {
                let inner = self.ty(cx, a)?;
                let (ty, long, truth, int16) = (inner.ty, inner.long, inner.truth, inner.int16);
                let mut t = typed(K::Paren(Box::new(inner)), ty, long, truth);
                t.int16 = int16;
                Some(t)
            }
            ExprKind::AxisSet(items) => {
                let mut typed_items = Vec::new();
                let mut ok = true;
                for i in items {
                    match self.ty(cx, i) {
                        Some(t) if t.ty == Ty::Str => {
                            self.want(
                                cx,
                                i,
                                Ty::Axis,
                                "an axis set holds axis numbers and axis sets",
                            );
                            ok = false;
                        }
                        Some(t) => typed_items.push(t),
                        None => ok = false,
                    }
                }
                // An axis set whatever its items: the type of what holds it can still be checked.
                Some(if ok {
                    typed(K::AxisSet(typed_items), Ty::Axis, false, false)
                } else {
                    placeholder(Ty::Axis, e.span)
                })
            }
            ExprKind::Name(n) if n.segments.len() == 1 && builtin(&n.text()).is_some() => {
                let kind = match builtin(&n.text()) {
                    Some(Builtin::Rnd) => K::Rnd(None),
                    _ => K::Timer,
                };
                Some(typed(kind, Ty::Num, false, false))
            }
            ExprKind::Name(n) => {
                let r = cx.keep(resolve(cx.registry(), n))?;
                if matches!(r.access, Access::Action | Access::Input) {
                    cx.push(Problem::error(
                        "pacer::check::not_readable",
                        n.span,
                        format!("{} has no value to read", r.name),
                        "not readable",
                    ));
                    return None;
                }
                let (ty, long) = if r.kind == Kind::BasicVar {
                    self.never_assigned(cx, &r.name, n.span);
                    (
                        var_type(&r.name).map_or(Ty::Num, |t| t.1),
                        r.ty == ValueType::Fixed(0),
                    )
                } else {
                    (Ty::Num, false)
                };
                // MotionBASIC's true is -1: a bit reads as -1 or 0.
                let negate = r.ty.is_bit();
                let int16 = r.kind == Kind::BasicVar && r.name.ends_with('%');
                let mut t = typed(K::Read { target: r, negate }, ty, long, false);
                t.int16 = int16;
                Some(t)
            }
            ExprKind::Unary(op, a) => {
                let why = match op {
                    UnOp::Neg => "`-` needs a number",
                    UnOp::Not => "NOT needs a number",
                };
                let Some(inner) = self.want(cx, a, Ty::Num, why) else {
                    return Some(placeholder(Ty::Num, e.span));
                };
                Some(match op {
                    UnOp::Neg => {
                        let (long, int16) = (inner.long, inner.int16);
                        let mut t = typed(K::Neg(Box::new(inner)), Ty::Num, long, false);
                        t.int16 = int16;
                        t
                    }
                    UnOp::Not => {
                        let truth = inner.truth;
                        typed(K::BitNot(Box::new(inner)), Ty::Num, false, truth)
                    }
                })
            }
            ExprKind::Binary(op, a, b) => {
                let ta = self.ty(cx, a)?;
                let tb = self.ty(cx, b)?;
                let compare = matches!(
                    op,
                    BinOp::Eq | BinOp::Ne | BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge
                );
                let same_eq = matches!(op, BinOp::Eq | BinOp::Ne) && ta.ty == tb.ty;
                // Strings join with `+` and compare character by character.
                let text = ta.ty == Ty::Str && tb.ty == Ty::Str && (compare || *op == BinOp::Add);
                if text {
                    let op_t = match op {
                        BinOp::Add => Op::Add,
                        cmp => Op::Cmp(super::powertools::cmp_of(*cmp)),
                    };
                    let ty = if compare { Ty::Num } else { Ty::Str };
                    return Some(typed(
                        K::Binary {
                            op: op_t,
                            a: Box::new(ta),
                            b: Box::new(tb),
                            negate: compare,
                        },
                        ty,
                        false,
                        compare,
                    ));
                }
                if !same_eq && (ta.ty != Ty::Num || tb.ty != Ty::Num) {
                    let (bad, t) = if ta.ty != Ty::Num {
                        (a, ta.ty)
                    } else {
                        (b, tb.ty)
                    };
                    let mut p = Problem::error(
                        "pacer::check::type",
                        bad.span,
                        format!("`{}` needs numbers, not {}", op.symbol(), word(t)),
                        format!("this is {}", word(t)),
                    );
                    if ta.ty == Ty::Str || tb.ty == Ty::Str {
                        p = p.with_help(
                            "a string and a number do not mix: STR$(x) makes a number a string, \
                             VAL(s$) a string a number",
                        );
                    }
                    cx.push(p);
                    return None;
                }
                let op_t = match op {
                    BinOp::Add => Op::Add,
                    BinOp::Sub => Op::Sub,
                    BinOp::Mul => Op::Mul,
                    BinOp::Div => Op::Div,
                    BinOp::Pow => Op::Pow,
                    BinOp::Mod => Op::BasicMod,
                    BinOp::IntDiv => Op::IntDiv,
                    // MotionBASIC's AND/OR/XOR are bitwise on integers (true is -1).
                    BinOp::And => Op::BitAnd,
                    BinOp::Or => Op::BitOr,
                    BinOp::Xor => Op::BitXor,
                    cmp => Op::Cmp(super::powertools::cmp_of(*cmp)),
                };
                let long = match op {
                    BinOp::IntDiv | BinOp::Mod => true,
                    BinOp::Add | BinOp::Sub | BinOp::Mul => ta.long && tb.long,
                    _ => false,
                };
                let truth = compare
                    || (matches!(op, BinOp::And | BinOp::Or | BinOp::Xor) && ta.truth && tb.truth);
                // INTEGER op INTEGER is INTEGER arithmetic (16 bits) in Microsoft BASIC; pacer
                // asks for one `%` operand, so constants alone keep computing as long integers.
                let int16 = matches!(op, BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::IntDiv)
                    && (ta.int16 || tb.int16)
                    && integer_operand(&ta)
                    && integer_operand(&tb);
                let mut t = typed(
                    K::Binary {
                        op: op_t,
                        a: Box::new(ta),
                        b: Box::new(tb),
                        negate: compare,
                    },
                    Ty::Num,
                    long,
                    truth,
                );
                t.int16 = int16;
                Some(t)
            }
            ExprKind::Call(f, args) => {
                if let Some(c) = controller(&f.text) {
                    let (Some(axes), Some(member)) =
                        (self.axis_args(cx, f, args), axis_member(c.member))
                    else {
                        return Some(placeholder(c.ty, e.span));
                    };
                    let truth = AXIS_TYPE.members[member as usize].ty.is_bit();
                    return Some(typed(
                        K::AxisRead {
                            member,
                            truth,
                            axes: Box::new(axes),
                        },
                        c.ty,
                        false,
                        false,
                    ));
                }
                if let Some(def) = super::text::find(&f.text) {
                    return self.text_call(cx, e, def, args);
                }
                if builtin(&f.text) == Some(Builtin::Rnd) {
                    if args.len() != 1 {
                        cx.push(Problem::error(
                            "pacer::check::arguments",
                            e.span,
                            format!("RND takes one argument or none, not {}", args.len()),
                            "wrong number of arguments",
                        ));
                        return None;
                    }
                    let x = self.want(cx, &args[0], Ty::Num, "RND takes a number")?;
                    return Some(typed(K::Rnd(Some(Box::new(x))), Ty::Num, false, false));
                }
                if array_call(&f.text) {
                    let el = self.element(cx, f, args, e.span)?;
                    self.never_assigned(cx, &format!("{}()", f.text), f.span);
                    let (ty, long) = (
                        var_type(&f.text).map_or(Ty::Num, |t| t.1),
                        el.base.ty == ValueType::Fixed(0),
                    );
                    let int16 = f.text.ends_with('%');
                    let mut t = typed(K::Element(Box::new(el)), ty, long, false);
                    t.int16 = int16;
                    return Some(t);
                }
                let math = functions::find(&f.text);
                let kernel = functions::find_kernel(&f.text);
                let found = math.map(|(_, n)| n).or(kernel.map(|(_, n)| n));
                let Some(arity) = found else {
                    let names = functions::FUNCTIONS
                        .iter()
                        .map(|f| f.0)
                        .chain(functions::KERNEL_FUNCTIONS.iter().map(|f| f.0))
                        .chain(CONTROLLERS.iter().map(|c| c.name));
                    cx.push(
                        Problem::error(
                            "pacer::check::unknown_function",
                            f.span,
                            format!("unknown function or controller variable `{}`", f.text),
                            "not known",
                        )
                        .with_help_opt(
                            nearest(&f.text, names).map(|n| format!("did you mean `{n}`?")),
                        ),
                    );
                    return None;
                };
                let mut ok = true;
                if args.len() != arity {
                    cx.push(Problem::error(
                        "pacer::check::arguments",
                        e.span,
                        format!(
                            "{} takes {arity} argument(s), not {}",
                            f.text.to_ascii_uppercase(),
                            args.len()
                        ),
                        "wrong number of arguments",
                    ));
                    ok = false;
                }
                let mut typed_args = Vec::new();
                for a in args {
                    match self.want(cx, a, Ty::Num, "function arguments are numbers") {
                        Some(t) => typed_args.push(t),
                        None => ok = false,
                    }
                }
                if !ok {
                    return Some(placeholder(Ty::Num, e.span));
                }
                let kind = match (math, kernel) {
                    (Some((func, _)), _) => K::Call(func, typed_args),
                    (None, Some((func, _))) => K::Kernel {
                        func,
                        args: typed_args,
                        // REGIST's and WRITE_SV's OK is a truth value: -1 in MotionBASIC.
                        negate: matches!(
                            func,
                            functions::KernelFunc::Regist | functions::KernelFunc::WriteSv
                        ),
                    },
                    (None, None) => return None,
                };
                Some(typed(kind, Ty::Num, false, false))
            }
        }
    }

    /// A variable read but assigned nowhere holds 0 (or an empty axis set) for ever: almost
    /// always a slip of the name.
    fn never_assigned(&mut self, cx: &mut Context<'_>, name: &str, span: Span) {
        let key = name.to_ascii_uppercase();
        if self.vars.assigned.contains(&key) || !self.warned.insert(key) {
            return;
        }
        let candidates = self
            .vars
            .assigned
            .iter()
            .filter_map(|k| self.vars.all.get(k).map(|(w, _)| w.as_str()));
        let help = match nearest(name, candidates) {
            Some(n) => {
                format!("`{n}` is assigned: did you mean it? As written, {name} is always 0")
            }
            None => format!("assign it before it is read; as written, {name} is always 0"),
        };
        cx.push(
            Problem::warning(
                "pacer::check::never_assigned",
                span,
                format!("{name} is read but never assigned"),
                "never assigned",
            )
            .with_help(help),
        );
    }
}

/// An operand of INTEGER arithmetic: an INTEGER expression, or a whole-number constant within
/// 16 bits (Microsoft BASIC types `1000` as INTEGER), signed or not.
fn integer_operand(t: &typed::Expr) -> bool {
    match &t.kind {
        _ if t.int16 => true,
        K::Const(_) => t.int_const,
        K::Neg(inner) | K::Paren(inner) => integer_operand(inner),
        _ => false,
    }
}

/// A value of type `ty` standing for an expression that has a problem: what holds it can still
/// be checked (the program never compiles with a problem, so it is never run).
fn placeholder(ty: Ty, span: Span) -> typed::Expr {
    typed::Expr {
        kind: K::Const(0.0),
        ty,
        long: false,
        int16: false,
        int_const: false,
        truth: false,
        span,
    }
}

/// The index of member `name` of the DSP axis object.
fn axis_member(name: &str) -> Option<u8> {
    AXIS_TYPE
        .members
        .iter()
        .position(|m| m.name == name)
        .map(|i| i as u8)
}

impl Rules for MotionBasic<'_> {
    fn dialect(&self) -> Dialect {
        Dialect::MotionBasic
    }

    fn resolve(&mut self, cx: &mut Context<'_>, name: &Name) -> Result<Resolved, Problem> {
        resolve(cx.registry(), name)
    }

    fn expr(&mut self, cx: &mut Context<'_>, e: &Expr, want: Want<'_>) -> Option<typed::Expr> {
        match want {
            Want::Any => self.ty(cx, e),
            Want::Number(why) | Want::Condition(why) => self.want(cx, e, Ty::Num, why),
        }
    }

    fn assign(&mut self, cx: &mut Context<'_>, target: &Name, value: &Expr) -> Option<T> {
        let Some(r) = cx.keep(resolve(cx.registry(), target)) else {
            self.ty(cx, value);
            return None;
        };
        let mut ok = true;
        if matches!(r.access, Access::Read) {
            cx.push(Problem::error(
                "pacer::check::read_only",
                target.span,
                format!("{} is read-only", r.name),
                "cannot be assigned",
            ));
            ok = false;
        }
        let want = if r.kind == Kind::BasicVar {
            var_type(&r.name).map_or(Ty::Num, |t| t.1)
        } else {
            Ty::Num
        };
        let v = self.want(
            cx,
            value,
            want,
            "the value must match the variable's type suffix",
        );
        let v = v.filter(|_| ok)?;
        if r.access == Access::Action {
            return Some(super::powertools::triggered(r, v));
        }
        Some(T::Assign {
            target: r,
            value: v,
        })
    }

    fn for_variable(&mut self, cx: &mut Context<'_>, var: &Name) -> Option<Resolved> {
        let r = cx.keep(resolve(cx.registry(), var))?;
        if r.kind != Kind::BasicVar || r.ty == ValueType::Integer {
            cx.push(Problem::error(
                "pacer::check::for",
                var.span,
                format!("{} cannot count a FOR loop", r.name),
                "not a numeric variable",
            ));
            return None;
        }
        Some(r)
    }

    /// A bare name that is no label: an object action (`Queue.0.QueueRemove`).
    fn gosub_unlabelled(&mut self, cx: &mut Context<'_>, seg: &Segment) -> Option<T> {
        let name = Name::from_token(&seg.text, seg.span.start);
        match cx.registry().resolve(&name) {
            Ok(r) if r.access == Access::Action => Some(T::Act {
                target: r,
                start: crate::devices::command::StartRef::Now,
                profile: 0,
                when: None,
            }),
            _ => {
                if let Some(message) = crate::registry::not_yet::motionbasic(&seg.text) {
                    cx.push(
                        Problem::error("pacer::check::not_yet", seg.span, message, "not run yet")
                            .with_help(crate::registry::not_yet::HELP),
                    );
                } else {
                    unknown_label(cx, seg, "no such subroutine");
                }
                None
            }
        }
    }

    fn other(&mut self, cx: &mut Context<'_>, s: &Stmt) -> Option<T> {
        match &s.kind {
            StmtKind::SetCall { target, .. } if array_call(&target.text) => self.storage(cx, s),
            StmtKind::SetCall {
                target,
                args,
                value,
            } if is_mid(&target.text) => self.mid_statement(cx, target, args, value),
            StmtKind::Dim(_)
            | StmtKind::Data(_)
            | StmtKind::Read(_)
            | StmtKind::Restore(_)
            | StmtKind::Swap(..)
            | StmtKind::Randomize(_)
            | StmtKind::DefType { .. }
            | StmtKind::OptionBase(_) => self.storage(cx, s),
            StmtKind::SetCall {
                target,
                args,
                value,
            } => {
                let Some(c) = controller(&target.text) else {
                    cx.push(unknown_controller(target));
                    return None;
                };
                let mut ok = true;
                if !c.writable {
                    cx.push(Problem::error(
                        "pacer::check::read_only",
                        target.span,
                        format!("{}@ is read-only", c.name),
                        "cannot be assigned",
                    ));
                    ok = false;
                }
                let axes = self.axis_args(cx, target, args);
                let value = self.want(
                    cx,
                    value,
                    c.ty,
                    "the value must match the controller variable",
                );
                let member = axis_member(c.member)?;
                let hook = AXIS_TYPE.members[member as usize].hook;
                Some(T::AxisWrite {
                    member,
                    hook,
                    axes: axes.filter(|_| ok)?,
                    value: value?,
                })
            }
            StmtKind::Gear { axis, form } => {
                let axes = self.want(cx, axis, Ty::Axis, "GEAR moves an axis: `GEAR knife~ …`");
                let (cmd, operands, after) = match form {
                    GearForm::At {
                        out,
                        inn,
                        pacer,
                        after,
                    } => {
                        let mut operands = Vec::new();
                        for e in [Some(out), Some(inn), pacer.as_ref()] {
                            operands.push(e.map(|e| {
                                self.want(cx, e, Ty::Num, "ratios and distances are numbers")
                            }));
                        }
                        let sensor = after.as_ref().and_then(after_sensor);
                        let slot = match (after, sensor) {
                            (Some(a), None) => Some(self.after_input(cx, a)),
                            _ => None,
                        };
                        let after = match (sensor, &slot) {
                            (Some(s), _) => GearAfter::Sensor(s),
                            (None, Some(_)) => GearAfter::Input,
                            (None, None) => GearAfter::Now,
                        };
                        (
                            MotionCmd::GearAt {
                                pacer: pacer.is_some(),
                                after,
                            },
                            operands,
                            slot,
                        )
                    }
                    GearForm::For { dist, pacer } => {
                        let operands = vec![
                            Some(self.want(cx, dist, Ty::Num, "distances are numbers")),
                            Some(self.want(cx, pacer, Ty::Num, "distances are numbers")),
                        ];
                        (MotionCmd::GearFor, operands, None)
                    }
                };
                motion(cmd, axes, operands, after)
            }
            StmtKind::Move { axis, form } => {
                let axes = self.want(cx, axis, Ty::Axis, "MOVE moves an axis: `MOVE web~ …`");
                let why = "positions, speeds and times are numbers";
                let (cmd, exprs): (MotionCmd, Vec<Option<&Expr>>) = match form {
                    MoveForm::At { speed, time } => (
                        MotionCmd::MoveAt {
                            time: time.is_some(),
                        },
                        vec![Some(speed), time.as_ref()],
                    ),
                    MoveForm::Position {
                        relative,
                        target,
                        speed,
                        time,
                    } => (
                        MotionCmd::MovePos {
                            relative: *relative,
                            speed: speed.is_some(),
                            time: time.is_some(),
                        },
                        vec![Some(target), speed.as_ref(), time.as_ref()],
                    ),
                };
                let operands = exprs
                    .into_iter()
                    .map(|e| e.map(|e| self.want(cx, e, Ty::Num, why)))
                    .collect();
                motion(cmd, axes, operands, None)
            }
            StmtKind::Print(items) => self.print(cx, items),
            StmtKind::PrintUsing(format, items) => {
                let format = self.want(cx, format, Ty::Str, "PRINT USING's format is a string");
                let mut values = Vec::new();
                let mut ok = true;
                for item in items {
                    if let PrintItem::Expr(e) = item {
                        match self.ty(cx, e) {
                            Some(t) if matches!(t.ty, Ty::Num | Ty::Str) => values.push(t),
                            Some(_) => {
                                self.want(cx, e, Ty::Num, "PRINT USING prints numbers and strings");
                                ok = false;
                            }
                            None => ok = false,
                        }
                    }
                }
                if values.len() > 64 {
                    cx.push(Problem::error(
                        "pacer::check::print",
                        s.span,
                        "PRINT USING takes at most 64 values",
                        "too many values",
                    ));
                    ok = false;
                }
                let newline =
                    !matches!(items.last(), Some(PrintItem::Semicolon | PrintItem::Comma));
                Some(T::PrintUsing {
                    format: format?,
                    values,
                    newline,
                })
                .filter(|_| ok)
            }
            StmtKind::WaitFor(e) => Some(T::WaitFor(self.want(cx, e, Ty::Num, "a number")?)),
            StmtKind::WaitTime(e) => Some(T::WaitTime(self.want(cx, e, Ty::Num, "a number")?)),
            _ => not_here(cx, s, Dialect::MotionBasic),
        }
    }
}

impl MotionBasic<'_> {
    /// A string function call.
    fn text_call(
        &mut self,
        cx: &mut Context<'_>,
        e: &Expr,
        def: &'static super::text::TextDef,
        args: &[Expr],
    ) -> Option<typed::Expr> {
        use super::text::{Arg, TextFunc};
        // INSTR's start is optional, in front.
        let kinds: &[Arg] = if def.func == TextFunc::Instr && args.len() == 2 {
            &def.args[1..]
        } else {
            def.args
        };
        let min = if def.func == TextFunc::Instr {
            2
        } else {
            def.min
        };
        if args.len() < min || args.len() > def.args.len() {
            let count = if min == def.args.len() {
                format!("{min}")
            } else {
                format!("{min} or {}", def.args.len())
            };
            cx.push(Problem::error(
                "pacer::check::arguments",
                e.span,
                format!("{} takes {count} arguments, not {}", def.name, args.len()),
                "wrong number of arguments",
            ));
            return None;
        }
        let mut typed_args = Vec::new();
        let mut ok = true;
        for (a, kind) in args.iter().zip(kinds) {
            let t = match kind {
                Arg::Num => self.want(cx, a, Ty::Num, &format!("{}: {}", def.name, def.meaning)),
                Arg::Text => self.want(cx, a, Ty::Str, &format!("{}: {}", def.name, def.meaning)),
                Arg::Either => self.ty(cx, a).filter(|t| {
                    let fits = matches!(t.ty, Ty::Num | Ty::Str);
                    if !fits {
                        self.want(cx, a, Ty::Num, "a character code or a string");
                    }
                    fits
                }),
            };
            match t {
                Some(t) => typed_args.push(t),
                None => ok = false,
            }
        }
        if !ok {
            return None;
        }
        let func = match def.func {
            TextFunc::Str(_) => {
                let arg = &args[0];
                let how = if typed_args[0].long && !real_literal(arg) {
                    typed::PrintHow::Integer
                } else {
                    print_precision(arg)
                };
                TextFunc::Str(how)
            }
            f => f,
        };
        let ty = if def.gives_text { Ty::Str } else { Ty::Num };
        let long = !def.gives_text && func != TextFunc::Val;
        Some(typed::Expr {
            kind: K::Text(func, typed_args),
            ty,
            long,
            int16: false,
            int_const: false,
            truth: false,
            span: e.span,
        })
    }

    /// An array element `seg(args)`.
    fn element(
        &mut self,
        cx: &mut Context<'_>,
        seg: &Segment,
        args: &[Expr],
        span: Span,
    ) -> Option<typed::Element> {
        let key = seg.text.to_ascii_uppercase();
        if self.first_array.is_none() {
            self.first_array = Some((seg.text.clone(), false));
        }
        let Some(array) = self.vars.arrays.get(&key).cloned() else {
            // Only at the REPL: a program's arrays are all collected before it is checked.
            cx.push(
                Problem::error(
                    "pacer::check::array",
                    seg.span,
                    format!("{} is not an array of the machine's programs", seg.text),
                    "no such array",
                )
                .with_help(
                    "arrays are dimensioned by the programs (DIM); a typed line uses theirs",
                ),
            );
            return None;
        };
        let mut subs = Vec::new();
        let mut ok = true;
        for a in args {
            match self.want(cx, a, Ty::Num, "a subscript is a number") {
                Some(t) => subs.push(t),
                None => ok = false,
            }
        }
        // A DIM that failed was reported at the DIM.
        let bounds = array.bounds.clone()?;
        if !array.declared && self.implicit.insert(key.clone()) {
            let near = nearest(
                &seg.text,
                functions::FUNCTIONS
                    .iter()
                    .map(|f| f.0)
                    .chain(super::text::TEXT_FUNCTIONS.iter().map(|d| d.name)),
            );
            let help = match near {
                Some(n) => format!(
                    "is `{n}(…)` meant? Otherwise write `DIM {}({})` to say how large it is",
                    seg.text,
                    vec!["10"; bounds.len()].join(", ")
                ),
                None => format!(
                    "write `DIM {}({})` to say how large it is",
                    seg.text,
                    vec!["10"; bounds.len()].join(", ")
                ),
            };
            cx.push(
                Problem::warning(
                    "pacer::check::implicit_array",
                    seg.span,
                    format!(
                        "{} is an array used without DIM: each subscript is {} to 10, as in \
                         Microsoft BASIC",
                        seg.text, array.lower
                    ),
                    "no DIM",
                )
                .with_help(help),
            );
        }
        if args.len() != bounds.len() {
            cx.push(Problem::error(
                "pacer::check::subscripts",
                span,
                format!(
                    "{} has {} subscript(s), not {}",
                    array.written,
                    bounds.len(),
                    args.len()
                ),
                "wrong number of subscripts",
            ));
            return None;
        }
        for (a, &b) in args.iter().zip(&bounds) {
            if let Some(v) = constant(a) {
                let r = v.round_ties_even();
                if r < f64::from(array.lower) || r > f64::from(b) {
                    cx.push(Problem::error(
                        SUBSCRIPT,
                        a.span,
                        format!(
                            "Subscript out of range: {v} is not within {} to {b}",
                            array.lower
                        ),
                        "out of range",
                    ));
                    ok = false;
                }
            }
        }
        let base_name = crate::registry::slot_name::array_key(&array.written, bounds.len());
        let vars = cx.registry().of(Kind::BasicVar);
        let &i = vars.names.get(&base_name)?;
        let slot = vars.slot(i, 0, false);
        let info = &cx.registry().slots[slot as usize];
        let base = Resolved {
            slot,
            ty: info.ty,
            access: Access::ReadWrite,
            hook: crate::registry::Hook::Store,
            kind: Kind::BasicVar,
            instance: i,
            name: array.written.clone(),
        };
        let text = var_type(&key).is_some_and(|t| t.1 == Ty::Str);
        ok.then_some(typed::Element {
            base,
            bounds,
            lower: array.lower,
            subs,
            text,
        })
    }

    /// A place `READ` or `SWAP` stores into: a variable of the programs or an array element.
    fn place(&mut self, cx: &mut Context<'_>, p: &Place) -> Option<(typed::Place, Ty)> {
        match p {
            Place::Var(n) => {
                let r = cx.keep(resolve(cx.registry(), n))?;
                if r.kind != Kind::BasicVar {
                    cx.push(Problem::error(
                        "pacer::check::place",
                        n.span,
                        format!("{} is not a variable of the program", r.name),
                        "not a variable",
                    ));
                    return None;
                }
                let ty = var_type(&r.name).map_or(Ty::Num, |t| t.1);
                if ty == Ty::Axis {
                    cx.push(Problem::error(
                        "pacer::check::place",
                        n.span,
                        format!("{} is an axis set", r.name),
                        "an axis set",
                    ));
                    return None;
                }
                Some((typed::Place::Var(r), ty))
            }
            Place::Element(seg, args, span) => {
                if !array_call(&seg.text) {
                    cx.push(Problem::error(
                        "pacer::check::place",
                        seg.span,
                        format!("{} is a function, not an array", seg.text),
                        "not an array",
                    ));
                    return None;
                }
                let el = self.element(cx, seg, args, *span)?;
                let ty = if el.text { Ty::Str } else { Ty::Num };
                Some((typed::Place::Element(el), ty))
            }
        }
    }

    /// `OPTION BASE e` at `span`: a literal 0 or 1, once, before the program's first array.
    fn option_base(&mut self, cx: &mut Context<'_>, span: Span, e: &Expr) -> Option<T> {
        const HELP: &str = "OPTION BASE 1 makes the subscripts of the program's arrays start \
                            at 1 (DIM A(10) is A(1) to A(10)); OPTION BASE 0, the default, at 0";
        let Some(b) = option_base(e) else {
            let message = match constant(e) {
                Some(v) if v != 0.0 && v != 1.0 => {
                    format!("OPTION BASE is 0 or 1, not {}", crate::diag::number(v))
                }
                _ => "OPTION BASE takes the number 0 or 1, written as such".to_string(),
            };
            cx.push(
                Problem::error("pacer::check::option_base", e.span, message, "not 0 or 1")
                    .with_help(HELP),
            );
            return None;
        };
        if self.option_base.is_some() {
            cx.push(
                Problem::error(
                    "pacer::check::option_base",
                    span,
                    "Duplicate Definition: a second OPTION BASE in this program",
                    "second OPTION BASE",
                )
                .with_help("a program says OPTION BASE once, before its first array"),
            );
            return None;
        }
        self.option_base = Some(span);
        if let Some((first, dim)) = &self.first_array {
            let how = if *dim { "dimensioned" } else { "used" };
            cx.push(
                Problem::error(
                    "pacer::check::option_base",
                    span,
                    format!(
                        "Duplicate Definition: OPTION BASE must come before the program's \
                         arrays, and {first} is already {how} above it"
                    ),
                    "after an array",
                )
                .with_help(
                    "write OPTION BASE before the program's first DIM or array use: an \
                     array's lowest subscript is fixed where its program first dimensions \
                     or uses it",
                ),
            );
            return None;
        }
        self.base = b;
        Some(T::Nothing)
    }

    /// The MotionBASIC statements of Microsoft BASIC's data and storage: DIM, DATA, READ,
    /// RESTORE, SWAP, RANDOMIZE, DEFINT …, and an array element's store.
    fn storage(&mut self, cx: &mut Context<'_>, s: &Stmt) -> Option<T> {
        match &s.kind {
            StmtKind::SetCall {
                target,
                args,
                value,
            } => {
                let span = Span::new(target.span.start, value.span.start);
                let el = self.element(cx, target, args, span);
                let want = if var_type(&target.text).is_some_and(|t| t.1 == Ty::Str) {
                    Ty::Str
                } else {
                    Ty::Num
                };
                let v = self.want(
                    cx,
                    value,
                    want,
                    "the value must match the array's type suffix",
                );
                Some(T::SetElement {
                    place: el?,
                    value: v?,
                })
            }
            StmtKind::Dim(arrays) => {
                let mut ok = true;
                for (seg, bounds) in arrays {
                    if let Err((span, why)) = dim_bounds(bounds) {
                        cx.push(Problem::error("pacer::check::dim", span, why, "not a size"));
                        ok = false;
                        continue;
                    }
                    if self.first_array.is_none() {
                        self.first_array = Some((seg.text.clone(), true));
                    }
                    let below = bounds
                        .iter()
                        .zip(dim_bounds(bounds).unwrap_or_default())
                        .find(|(_, b)| *b < self.base);
                    if let Some((e, b)) = below {
                        cx.push(
                            Problem::error(
                                "pacer::check::dim",
                                e.span,
                                format!(
                                    "Subscript out of range: under OPTION BASE {}, a bound is at least {0}, not {b}",
                                    self.base
                                ),
                                "no element",
                            )
                            .with_help("OPTION BASE 1 makes an array's subscripts run from 1 to its bound"),
                        );
                        ok = false;
                        continue;
                    }
                    let key = seg.text.to_ascii_uppercase();
                    if !self.dimensioned.insert(key.clone()) {
                        cx.push(Problem::error(
                            "pacer::check::dim",
                            seg.span,
                            format!("Duplicate Definition: {} is dimensioned twice", seg.text),
                            "second DIM",
                        ));
                        ok = false;
                        continue;
                    }
                    let Some(array) = self.vars.arrays.get(&key) else {
                        // Only at the REPL: a program's DIMs are all collected first.
                        cx.push(
                            Problem::error(
                                "pacer::check::array",
                                seg.span,
                                format!("{} cannot be dimensioned here", seg.text),
                                "not an array of the programs",
                            )
                            .with_help(
                                "arrays are dimensioned by the programs' DIM, before the run",
                            ),
                        );
                        ok = false;
                        continue;
                    };
                    let wanted = dim_bounds(bounds).unwrap_or_default();
                    match &array.bounds {
                        None => {
                            cx.push(Problem::error(
                                "pacer::check::dim",
                                seg.span,
                                format!(
                                    "{} is too large: the arrays of a machine hold at most {MAX_ELEMENTS} elements in all",
                                    seg.text
                                ),
                                "too large",
                            ));
                            ok = false;
                        }
                        Some(b) if *b != wanted => {
                            cx.push(Problem::error(
                                "pacer::check::dim",
                                seg.span,
                                format!(
                                    "{} is dimensioned differently elsewhere ({:?} here, {:?} there)",
                                    seg.text, wanted, b
                                ),
                                "a different size",
                            ));
                            ok = false;
                        }
                        Some(_) if array.lower != self.base => {
                            cx.push(Problem::error(
                                "pacer::check::dim",
                                seg.span,
                                format!(
                                    "{} is dimensioned differently elsewhere (subscripts from {} here, under OPTION BASE {1}; from {} there)",
                                    seg.text, self.base, array.lower
                                ),
                                "a different OPTION BASE",
                            ));
                            ok = false;
                        }
                        Some(_) => {}
                    }
                    for b in bounds {
                        self.ty(cx, b);
                    }
                }
                ok.then_some(T::Nothing)
            }
            StmtKind::OptionBase(e) => self.option_base(cx, s.span, e),
            StmtKind::Data(items) => Some(T::Data(
                items
                    .iter()
                    .map(|i| typed::DataConst {
                        text: i.text.clone(),
                        number: if i.quoted { None } else { data_number(&i.text) },
                        span: i.span,
                    })
                    .collect(),
            )),
            StmtKind::Read(places) => {
                let mut out = Vec::new();
                let mut ok = true;
                for p in places {
                    match self.place(cx, p) {
                        Some((place, _)) => out.push(place),
                        None => ok = false,
                    }
                }
                ok.then_some(T::Read(out))
            }
            StmtKind::Restore(None) => Some(T::Restore(None)),
            StmtKind::Restore(Some(seg)) => {
                let key = super::walk::label_key(&seg.text);
                if !cx.labels.contains_key(&key) {
                    unknown_label(cx, seg, "no such label");
                    return None;
                }
                Some(T::Restore(Some(key)))
            }
            StmtKind::Swap(a, b) => {
                let pa = self.place(cx, a);
                let pb = self.place(cx, b);
                let ((pa, ta), (pb, tb)) = (pa?, pb?);
                let vt = |p: &typed::Place| match p {
                    typed::Place::Var(r) => r.ty,
                    typed::Place::Element(e) => e.base.ty,
                };
                if ta != tb || vt(&pa) != vt(&pb) {
                    cx.push(
                        Problem::error(
                            "pacer::check::swap",
                            Span::new(a.span().start, b.span().end),
                            "Type mismatch: SWAP exchanges two values of the same type",
                            "different types",
                        )
                        .with_help("both names need the same type suffix"),
                    );
                    return None;
                }
                Some(T::Swap(pa, pb))
            }
            StmtKind::Randomize(None) => Some(T::Randomize(None)),
            StmtKind::Randomize(Some(e)) => Some(T::Randomize(Some(self.want(
                cx,
                e,
                Ty::Num,
                "the seed is a number",
            )?))),
            StmtKind::DefType { .. } => Some(T::Nothing),
            _ => not_here(cx, s, Dialect::MotionBasic),
        }
    }

    /// The `MID$(v$, start[, n]) = y$` statement: `v$` a string variable or element.
    fn mid_statement(
        &mut self,
        cx: &mut Context<'_>,
        target: &Segment,
        args: &[Expr],
        value: &Expr,
    ) -> Option<T> {
        let usage = "write `MID$(A$, start) = B$` or `MID$(A$, start, count) = B$`";
        let (first, start, count) = match args {
            [first, start] => (first, start, None),
            [first, start, count] => (first, start, Some(count)),
            _ => {
                cx.push(
                    Problem::error(
                        "pacer::check::mid",
                        target.span,
                        format!(
                            "the MID$ statement takes 2 or 3 arguments, not {}",
                            args.len()
                        ),
                        "wrong number of arguments",
                    )
                    .with_help(usage),
                );
                return None;
            }
        };
        let place = match &first.kind {
            ExprKind::Name(n) => Some(Place::Var(n.clone())),
            ExprKind::Call(seg, subs) if array_call(&seg.text) => {
                Some(Place::Element(seg.clone(), subs.clone(), first.span))
            }
            _ => None,
        };
        let Some(place) = place else {
            cx.push(
                Problem::error(
                    "pacer::check::mid",
                    first.span,
                    "the MID$ statement changes a string variable or array element",
                    "not a variable",
                )
                .with_help(usage),
            );
            return None;
        };
        let placed = self.place(cx, &place);
        let start = self.want(cx, start, Ty::Num, "the start is a number");
        let count = count.map(|c| self.want(cx, c, Ty::Num, "the count is a number"));
        let value = self.want(cx, value, Ty::Str, "MID$ = puts a string into a string");
        let (place, ty) = placed?;
        if ty != Ty::Str {
            cx.push(
                Problem::error(
                    "pacer::check::type",
                    first.span,
                    "Type mismatch: the MID$ statement changes a string",
                    "not a string",
                )
                .with_help("the variable needs the `$` suffix (or a DEFSTR letter)"),
            );
            return None;
        }
        let count = match count {
            Some(c) => Some(c?),
            None => None,
        };
        Some(T::MidSet {
            place,
            start: start?,
            count,
            value: value?,
        })
    }

    /// `PRINT`: numbers and strings; every item checked, each number written as its type.
    fn print(&mut self, cx: &mut Context<'_>, items: &[PrintItem]) -> Option<T> {
        let mut checked = Vec::with_capacity(items.len());
        let mut ok = true;
        for item in items {
            match item {
                PrintItem::Semicolon => checked.push(typed::PrintItem::Semicolon),
                PrintItem::Comma => checked.push(typed::PrintItem::Comma),
                PrintItem::Expr(e) => {
                    let Some(t) = self.ty(cx, e) else {
                        ok = false;
                        continue;
                    };
                    let how = match t.ty {
                        Ty::Str => typed::PrintHow::Text,
                        Ty::Axis => {
                            cx.push(Problem::error(
                                "pacer::check::print",
                                e.span,
                                "an axis set cannot be printed",
                                "an axis set",
                            ));
                            ok = false;
                            continue;
                        }
                        Ty::Num | Ty::Bool if t.long && !real_literal(e) => {
                            typed::PrintHow::Integer
                        }
                        Ty::Num | Ty::Bool => print_precision(e),
                    };
                    checked.push(typed::PrintItem::Value(t, how));
                }
            }
        }
        ok.then_some(T::Print(checked))
    }
}

/// A literal written with a point, an exponent or a real suffix (`1E7`, `2.0`, `2!`): a SINGLE
/// or DOUBLE in Microsoft BASIC even when its value is whole.
fn real_literal(e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Number(_, form) => {
            matches!(form, NumForm::Real | NumForm::Single | NumForm::Double)
        }
        ExprKind::Paren(a) | ExprKind::Unary(UnOp::Neg, a) => real_literal(a),
        _ => false,
    }
}

/// Microsoft BASIC's type of a real expression for PRINT: DOUBLE when it reads a `#` variable
/// or holds a literal of more than 7 significant digits, SINGLE otherwise.
fn print_precision(e: &Expr) -> typed::PrintHow {
    fn double(e: &Expr) -> bool {
        match &e.kind {
            ExprKind::Name(n) => n.text().ends_with('#'),
            ExprKind::Number(_, NumForm::Double) => true,
            ExprKind::Number(_, NumForm::Single) => false,
            ExprKind::Number(x, _) => {
                let digits = format!("{:e}", x.abs());
                let mantissa = digits.split('e').next().unwrap_or_default();
                mantissa.chars().filter(char::is_ascii_digit).count() > 7
            }
            ExprKind::Unary(_, a) | ExprKind::Paren(a) => double(a),
            ExprKind::Binary(_, a, b) => double(a) || double(b),
            ExprKind::Call(_, args) | ExprKind::AxisSet(args) => args.iter().any(double),
            ExprKind::Bool(_) | ExprKind::Str(_) => false,
        }
    }
    if double(e) {
        typed::PrintHow::Double
    } else {
        typed::PrintHow::Single
    }
}

/// The sensors `AFTER` names on a DSP axis's card.
const SENSOR_NAMES: [(&str, Sensor); 3] = [
    ("ZREF", Sensor::Zref),
    ("ASEN", Sensor::Asen),
    ("BSEN", Sensor::Bsen),
];

/// `AFTER ZREF|ASEN|BSEN` (any case): the sensor of the axis's card the gear starts on.
fn after_sensor(e: &Expr) -> Option<Sensor> {
    match &e.kind {
        ExprKind::Name(n) if n.segments.len() == 1 => {
            let text = n.text();
            SENSOR_NAMES
                .iter()
                .find(|(s, _)| s.eq_ignore_ascii_case(&text))
                .map(|&(_, w)| w)
        }
        _ => None,
    }
}

/// A motion statement whose parts all checked.
fn motion(
    cmd: MotionCmd,
    axes: Option<typed::Expr>,
    operands: Vec<Option<Option<typed::Expr>>>,
    after: Option<Option<u32>>,
) -> Option<T> {
    let axes = axes?;
    let mut checked = Vec::new();
    for o in operands {
        match o {
            None => checked.push(None),
            Some(t) => checked.push(Some(t?)),
        }
    }
    let after = match after {
        None => None,
        Some(slot) => Some(slot?),
    };
    Some(T::Motion {
        cmd,
        axes,
        operands: checked,
        after,
    })
}

fn unknown_controller(target: &Segment) -> Problem {
    let names = CONTROLLERS.iter().map(|c| c.name);
    Problem::error(
        "pacer::check::unknown_controller",
        target.span,
        format!("unknown controller variable `{}`", target.text),
        "not a controller variable",
    )
    .with_help_opt(
        nearest(target.text.trim_end_matches('@'), names).map(|n| format!("did you mean `{n}@`?")),
    )
}

/// A `DATA` item's value when the whole item reads as a number (`12`, `-3.5`, `1E3`, `.5`).
pub fn data_number(text: &str) -> Option<f64> {
    let t = text.trim();
    let plain = t.strip_prefix('+').unwrap_or(t);
    let ok = !plain.is_empty()
        && plain
            .chars()
            .all(|c| c.is_ascii_digit() || matches!(c, '.' | 'E' | 'e' | 'D' | 'd' | '-' | '+'))
        && plain
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_digit() || c == '.' || c == '-');
    if !ok {
        return None;
    }
    plain
        .replace(['D', 'd'], "E")
        .parse()
        .ok()
        .filter(|v: &f64| v.is_finite())
}
