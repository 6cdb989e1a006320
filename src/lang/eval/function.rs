//! POV-Ray's `function { }` compiled once into a `FloatFunction` (`crate::function`): names
//! are resolved as the function is declared (parameters to their places, declared numbers to
//! constants, declared functions to calls), so a call runs the program, not the syntax.

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;

use super::{Evaluator, Pigment};
use crate::diagnostic::{SceneError, Span};
use crate::function::{
    Binary, Builder, ColourFunction, FloatFunction, GRAY, MAX_STACK, Op, PatternField,
    PigmentChannel, Unary,
};
use crate::graph::{Pattern, compose};
use crate::lang::keywords::{Constant, Function};
use crate::lang::syntax::{
    Appearance, BinaryOp, Call, Expr, ExprKind, FunctionBody, FunctionDef, Ident, UnaryOp,
};
use crate::lang::value::Value;
use crate::texture::ImageMap;

/// POV-Ray's number of its built-in noise, `f_noise3d` (`internal(76)`).
const NOISE_3D: f64 = 76.0;

impl Evaluator {
    /// What `#declare F = function { ... }` binds: a float function, or a colour function.
    pub(super) fn function_value(&mut self, def: &FunctionDef) -> Result<Value, SceneError> {
        Ok(match &def.body {
            FunctionBody::Expr(_) | FunctionBody::Pattern(_) => {
                Value::Function(self.float_function(def)?)
            }
            FunctionBody::Pigment(pigment) => {
                no_parameters(def, "a colour function")?;
                Value::ColourFunction(self.colour_function(pigment)?)
            }
            FunctionBody::Transform(t) => {
                no_parameters(def, "a transform function")?;
                Value::TransformFunction(Arc::new(self.transform(t)?.to_affine()))
            }
        })
    }

    /// The colour function of `pigment`, compiled (its images read).
    pub(super) fn colour_function(
        &mut self,
        pigment: &Appearance,
    ) -> Result<Arc<ColourFunction>, SceneError> {
        let made = self.pigment(pigment, &Pigment::black())?;
        let mut load = |path: &Path| ImageMap::load(path).map(Arc::new);
        let function = ColourFunction::new(made.colour, made.filter, made.through, &mut load)
            .map_err(|e| SceneError::at(&pigment.span, e.to_string()))?;
        Ok(Arc::new(function))
    }

    /// `pigment_pattern { }`: the gray of `pigment`'s colour, as a function of (x, y, z).
    pub(super) fn gray_function(
        &mut self,
        pigment: &Appearance,
    ) -> Result<Arc<FloatFunction>, SceneError> {
        let function = self.colour_function(pigment)?;
        let mut program = Builder::new(3);
        let gray = Op::Pigment(Box::new(PigmentChannel { function, channel: GRAY }));
        for op in [Op::Parameter(0), Op::Parameter(1), Op::Parameter(2), gray] {
            emit(&mut program, op, &pigment.span)?;
        }
        Ok(Arc::new(program.finish()))
    }

    /// The compiled function `def` declares.
    pub(super) fn float_function(
        &mut self,
        def: &FunctionDef,
    ) -> Result<Arc<FloatFunction>, SceneError> {
        let parameters: Vec<String> = if def.parameters.is_empty() {
            ["x", "y", "z"].map(String::from).to_vec()
        } else {
            def.parameters.iter().map(|p| p.name.clone()).collect()
        };
        for (i, p) in def.parameters.iter().enumerate() {
            if parameters[..i].contains(&p.name) {
                return Err(SceneError::at(
                    &p.span,
                    format!("parameter `{}` is named twice", p.name),
                ));
            }
        }
        let mut program = Builder::new(parameters.len());
        match &def.body {
            FunctionBody::Expr(body) => self.compile(body, &parameters, &mut program)?,
            FunctionBody::Pattern(texture) => {
                if !def.parameters.is_empty() {
                    return Err(SceneError::at(
                        &def.span,
                        "a pattern's function takes x, y and z: it has no parameters of its own",
                    ));
                }
                let node = self.texture(texture)?;
                let Pattern::Field { shape, .. } = node.pattern else {
                    return Err(SceneError::at(
                        &texture.span,
                        "this pattern has no value of its own (`average` averages a map)",
                    ));
                };
                let pattern =
                    PatternField { shape: *shape, to_pattern: compose(&node.transforms).inverse() };
                for op in [Op::Parameter(0), Op::Parameter(1), Op::Parameter(2)] {
                    emit(&mut program, op, &def.span)?;
                }
                emit(&mut program, Op::Pattern(Box::new(pattern)), &def.span)?;
            }
            FunctionBody::Pigment(pigment) => {
                return Err(SceneError::at(
                    &pigment.span,
                    "a colour function gives a colour where a number is wanted: declare it and \
                     take a component of its value (`F(x, y, z).gray`)",
                ));
            }
            FunctionBody::Transform(t) => {
                return Err(SceneError::at(
                    &t.span,
                    "a transform function gives a point where a number is wanted: declare it \
                     and call it from the scene (`F(x, y, z)`)",
                ));
            }
        }
        Ok(Arc::new(program.finish()))
    }

    /// Appends the program of `expr` to `program`.
    fn compile(
        &mut self,
        expr: &Expr,
        parameters: &[String],
        program: &mut Builder,
    ) -> Result<(), SceneError> {
        let at = &expr.span;
        let parameter = |name: &str| parameters.iter().position(|p| p == name);
        let op = match &expr.kind {
            ExprKind::Number(v) => Op::Number(*v),
            ExprKind::Constant(c) => {
                let word = match c {
                    Constant::X => "x",
                    Constant::Y => "y",
                    Constant::Z => "z",
                    Constant::Pi
                    | Constant::True
                    | Constant::False
                    | Constant::Clock
                    | Constant::FrameNumber
                    | Constant::ClockOn
                    | Constant::ClockDelta => return self.constant(expr, program),
                };
                match parameter(word) {
                    Some(i) => Op::Parameter(i),
                    None => {
                        return Err(SceneError::at(
                            at,
                            format!("`{word}` is not a parameter of this function"),
                        ));
                    }
                }
            }
            // POV-Ray's `u` and `v` are the first two of a function's x, y and z.
            ExprKind::Ident(name) => match parameter(name).or_else(|| match name.as_str() {
                "u" => parameter("x"),
                "v" => parameter("y"),
                _ => None,
            }) {
                Some(i) => Op::Parameter(i),
                None => match self.lookup(name) {
                    Some(Value::Float(v)) => Op::Number(*v),
                    Some(Value::Function(_)) => {
                        return Err(SceneError::at(
                            at,
                            format!("`{name}` is a function: call it as `{name}(...)`"),
                        ));
                    }
                    Some(other) => {
                        return Err(SceneError::at(
                            at,
                            format!(
                                "`{name}` is {}: a function computes with numbers",
                                other.kind()
                            ),
                        ));
                    }
                    None => {
                        let ident = Ident { name: name.clone(), span: at.clone() };
                        return Err(self.unknown(&ident));
                    }
                },
            },
            ExprKind::Unary { op, operand } => {
                self.compile(operand, parameters, program)?;
                match op {
                    UnaryOp::Plus => return Ok(()),
                    UnaryOp::Negate => Op::Unary(Unary::Negate),
                    UnaryOp::Not => Op::Unary(Unary::Not),
                }
            }
            ExprKind::Binary { op, left, right, .. } => {
                self.compile(left, parameters, program)?;
                self.compile(right, parameters, program)?;
                Op::Binary(match op {
                    BinaryOp::Or => Binary::Or,
                    BinaryOp::And => Binary::And,
                    BinaryOp::Less => Binary::Less,
                    BinaryOp::LessEqual => Binary::LessEqual,
                    BinaryOp::Greater => Binary::Greater,
                    BinaryOp::GreaterEqual => Binary::GreaterEqual,
                    BinaryOp::Equal => Binary::Equal,
                    BinaryOp::NotEqual => Binary::NotEqual,
                    BinaryOp::Add => Binary::Add,
                    BinaryOp::Subtract => Binary::Subtract,
                    BinaryOp::Multiply => Binary::Multiply,
                    BinaryOp::Divide => Binary::Divide,
                })
            }
            ExprKind::Ternary { condition, then, otherwise } => {
                for part in [condition, then, otherwise] {
                    self.compile(part, parameters, program)?;
                }
                Op::Choose
            }
            ExprKind::Function(f, args) => match built_in(*f) {
                Some(op) => {
                    for arg in args {
                        self.compile(arg, parameters, program)?;
                    }
                    op
                }
                None => return self.constant(expr, program),
            },
            ExprKind::Call(call) => return self.compile_call(call, parameters, program),
            ExprKind::Component { value, axis, .. } => {
                if let ExprKind::Call(call) = &value.kind
                    && let Some(Value::ColourFunction(f)) = self.lookup(&call.name.name)
                {
                    let function = f.clone();
                    check_count(call, 3)?;
                    for arg in &call.arguments {
                        self.compile(arg, parameters, program)?;
                    }
                    Op::Pigment(Box::new(PigmentChannel { function, channel: *axis }))
                } else {
                    // A component of a declared vector: its value as the function is declared.
                    return self.constant(expr, program);
                }
            }
            // An element of a declared array: its value as the function is declared.
            ExprKind::Index { .. } => {
                return self.constant(expr, program);
            }
            ExprKind::Vector(_)
            | ExprKind::String(_)
            | ExprKind::Rgb(_)
            | ExprKind::PovColour(..)
            | ExprKind::ColourParts { .. }
            | ExprKind::Block(_) => {
                return Err(SceneError::at(
                    at,
                    "a function computes numbers: a vector, colour, string or block cannot stand \
                     in it",
                ));
            }
        };
        emit(program, op, at)
    }

    /// A call in a function: a declared function, POV-Ray's `internal(n)`, or a macro whose
    /// value is a number as the function is declared.
    fn compile_call(
        &mut self,
        call: &Call,
        parameters: &[String],
        program: &mut Builder,
    ) -> Result<(), SceneError> {
        let name = call.name.name.as_str();
        if name == "internal" && self.lookup(name).is_none() {
            let [number] = call.arguments.as_slice() else {
                return Err(SceneError::at(&call.span, "`internal` takes one number"));
            };
            let n = self.number(number, "`internal`")?;
            let xyz = parameters.len() == 3
                && ["x", "y", "z"].iter().zip(parameters).all(|(a, b)| a == b);
            if n != NOISE_3D || !xyz {
                return Err(SceneError::at(
                    &call.span,
                    format!(
                        "POV-Ray's `internal({n})` is not built into raydiance: its functions.inc \
                         writes the `f_` functions by their formulas (`internal(76)`, the noise, \
                         is built in, in a function of x, y and z)"
                    ),
                ));
            }
            for op in [Op::Parameter(0), Op::Parameter(1), Op::Parameter(2), Op::Noise] {
                emit(program, op, &call.span)?;
            }
            return Ok(());
        }
        match self.lookup(name) {
            Some(Value::ColourFunction(_)) => Err(SceneError::at(
                &call.span,
                format!(
                    "`{name}` is a colour function: a function computes with numbers, so take a \
                     component of its colour (`{name}(x, y, z).red`, `.gray`)"
                ),
            )),
            Some(Value::Function(f)) => {
                let f = f.clone();
                check_arguments(call, &f)?;
                for arg in &call.arguments {
                    self.compile(arg, parameters, program)?;
                }
                emit(program, Op::Call(f), &call.span)
            }
            _ => {
                let expr = Expr { kind: ExprKind::Call(call.clone()), span: call.span.clone() };
                self.constant(&expr, program)
            }
        }
    }

    /// `expr`'s value as the function is declared, a number.
    fn constant(&mut self, expr: &Expr, program: &mut Builder) -> Result<(), SceneError> {
        let value = self.number(expr, "a function")?;
        emit(program, Op::Number(value), &expr.span)
    }

    /// A declared function called from the scene: `F(1, 2, 3)`.
    pub(super) fn call_function(
        &mut self,
        f: &FloatFunction,
        call: &Call,
    ) -> Result<Value, SceneError> {
        check_arguments(call, f)?;
        let mut arguments = Vec::with_capacity(call.arguments.len());
        for arg in &call.arguments {
            arguments.push(self.number(arg, &format!("`{}`", call.name.name))?);
        }
        Ok(Value::Float(f.eval(&arguments)))
    }

    /// A declared colour function called from the scene: `F(1, 2, 3)`, the colour there.
    pub(super) fn call_colour_function(
        &mut self,
        f: &ColourFunction,
        call: &Call,
    ) -> Result<Value, SceneError> {
        check_count(call, 3)?;
        let mut p = [0.0; 3];
        for (coordinate, arg) in p.iter_mut().zip(&call.arguments) {
            *coordinate = self.number(arg, &format!("`{}`", call.name.name))? as f32;
        }
        Ok(Value::Numbers(f.colour(Vec3::from(p)).to_vec()))
    }
}

/// An error unless `def`, `what` of x, y and z, names no parameters of its own.
fn no_parameters(def: &FunctionDef, what: &str) -> Result<(), SceneError> {
    match def.parameters.is_empty() {
        true => Ok(()),
        false => Err(SceneError::at(
            &def.span,
            format!("{what} takes x, y and z: it has no parameters of its own"),
        )),
    }
}

fn check_arguments(call: &Call, f: &FloatFunction) -> Result<(), SceneError> {
    check_count(call, f.parameters())
}

/// An error unless `call` gives `wanted` arguments.
fn check_count(call: &Call, wanted: usize) -> Result<(), SceneError> {
    let given = call.arguments.len();
    if given == wanted {
        return Ok(());
    }
    let plural = if wanted == 1 { "" } else { "s" };
    Err(SceneError::at(
        &call.span,
        format!("function `{}` takes {wanted} argument{plural}, not {given}", call.name.name),
    ))
}

fn emit(program: &mut Builder, op: Op, at: &Span) -> Result<(), SceneError> {
    program.push(op).map_err(|depth| {
        SceneError::at(
            at,
            format!("this function needs a stack {depth} deep: at most {MAX_STACK} are allowed"),
        )
    })
}

/// The op of a built-in function within a function; `None` for those of the scene language
/// alone (vectors, strings, streams), which a function takes as constants.
fn built_in(f: Function) -> Option<Op> {
    use Function::*;
    Some(match f {
        Sin => Op::Unary(Unary::Sin),
        Cos => Op::Unary(Unary::Cos),
        Tan => Op::Unary(Unary::Tan),
        Asin => Op::Unary(Unary::Asin),
        Acos => Op::Unary(Unary::Acos),
        Atan => Op::Unary(Unary::Atan),
        Sinh => Op::Unary(Unary::Sinh),
        Cosh => Op::Unary(Unary::Cosh),
        Tanh => Op::Unary(Unary::Tanh),
        Asinh => Op::Unary(Unary::Asinh),
        Acosh => Op::Unary(Unary::Acosh),
        Atanh => Op::Unary(Unary::Atanh),
        Sqrt => Op::Unary(Unary::Sqrt),
        Sqr => Op::Unary(Unary::Sqr),
        Abs => Op::Unary(Unary::Abs),
        Exp => Op::Unary(Unary::Exp),
        Ln => Op::Unary(Unary::Ln),
        Log => Op::Unary(Unary::Log),
        Floor => Op::Unary(Unary::Floor),
        Ceil => Op::Unary(Unary::Ceil),
        Int => Op::Unary(Unary::Int),
        Radians => Op::Unary(Unary::Radians),
        Degrees => Op::Unary(Unary::Degrees),
        Pow => Op::Binary(Binary::Pow),
        Min => Op::Binary(Binary::Min),
        Max => Op::Binary(Binary::Max),
        Mod => Op::Binary(Binary::Mod),
        Atan2 => Op::Binary(Binary::Atan2),
        Select => Op::Select3,
        Vlength | Vnormalize | Vdot | Vcross | Vrotate | VaxisRotate | Vturbulence | Seed
        | Rand | Concat | Str | Vstr | Strlen | Substr | Strupr | Strlwr | Chr | Asc | Val
        | FileExists | Defined | DimensionSize | Dimensions | Div | MinExtent | MaxExtent
        | Trace | Inside => {
            return None;
        }
    })
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::graph::SceneGraph;

    fn pov(text: &str) -> Result<SceneGraph, String> {
        crate::lang::parse_scene(Path::new("functions.pov"), text).map_err(|e| e.to_string())
    }

    /// Checks, in a scene, that each `function(a) { ... }` at its argument gives what its
    /// definition written in the scene language gives.
    fn agrees(cases: &[(&str, &str, &str)]) {
        let mut text = String::from(
            "#macro Near(A, B, What)\n\
             #if (abs(A - B) > 1e-9 * max(1, abs(B))) #error concat(What, \" differs: \", \
             str(A, 0, 12), \" \", str(B, 0, 12)) #end\n#end\n",
        );
        for (i, (body, a, definition)) in cases.iter().enumerate() {
            text += &format!(
                "#declare F{i} = function(a) {{ {body} }}\n#declare a = {a};\n\
                 Near(F{i}({a}), {definition}, \"{body}\")\n#undef a\n"
            );
        }
        pov(&text).unwrap_or_else(|e| panic!("{e}"));
    }

    #[test]
    fn each_built_in_computes_its_definition() {
        agrees(&[
            // Its Taylor series to the 11th power, in Horner's form.
            (
                "sin(a)",
                "0.3",
                "0.3 * (1 - 0.015 * (1 - 0.0045 * (1 - 0.09 / 42 * (1 - 0.09 / 72))))",
            ),
            ("cos(a)", "0.3", "sqrt(1 - pow(sin(0.3), 2))"),
            ("tan(a)", "0.3", "sin(0.3) / cos(0.3)"),
            ("asin(a)", "0.3", "atan(0.3 / sqrt(1 - 0.09))"),
            ("acos(a)", "0.3", "pi / 2 - asin(0.3)"),
            ("atan(a)", "0.3", "asin(0.3 / sqrt(1.09))"),
            ("sinh(a)", "0.3", "(exp(0.3) - exp(-0.3)) / 2"),
            ("cosh(a)", "0.3", "(exp(0.3) + exp(-0.3)) / 2"),
            ("tanh(a)", "0.3", "(exp(0.6) - 1) / (exp(0.6) + 1)"),
            ("asinh(a)", "0.3", "ln(0.3 + sqrt(1.09))"),
            ("acosh(a)", "1.3", "ln(1.3 + sqrt(0.69))"),
            ("atanh(a)", "0.3", "ln(1.3 / 0.7) / 2"),
            ("sqrt(a)", "2", "exp(ln(2) / 2)"),
            ("sqr(a)", "-3", "9"),
            ("abs(a)", "-3", "3"),
            ("exp(a)", "1", "2.718281828459045"),
            ("ln(a)", "10", "2.302585092994046"),
            ("log(a)", "1000", "3"),
            ("floor(a)", "-2.5", "-3"),
            ("ceil(a)", "-2.5", "-2"),
            ("int(a)", "-2.5", "-2"),
            ("radians(a)", "180", "pi"),
            ("degrees(a)", "pi", "180"),
            ("pow(a, 3)", "2", "8"),
            ("min(a, 1)", "2", "1"),
            ("max(a, 1)", "2", "2"),
            ("mod(a, 3)", "-7", "-1"),
            ("atan2(a, -1)", "1", "3 * pi / 4"),
            ("select(a, 1, 2)", "-1", "1"),
            ("select(a, 1, 2)", "0", "2"),
            ("a < 2 & a >= 1 | a = 7", "1", "1"),
            ("a != 1", "1", "0"),
            ("!(a > 0)", "1", "0"),
            ("a > 0 ? -a : a * a", "2", "-2"),
            ("-a + +a * 2 / 4 - 1", "4", "-3"),
        ]);
    }

    #[test]
    fn a_wrong_definition_is_caught() {
        let result = std::panic::catch_unwind(|| agrees(&[("sinh(a)", "0.3", "sin(0.3)")]));
        assert!(result.is_err(), "the check can fail");
    }

    #[test]
    fn functions_inc_computes_povray_s_documented_functions() {
        // Each against its definition at points: distances, angles, solids (negative inside),
        // the noise and the patterns.
        pov(r#"
#include "functions.inc"
#macro Near(A, B, What)
  #if (abs(A - B) > 1e-9) #error concat(What, " differs: ", str(A, 0, 12), " ", str(B, 0, 12)) #end
#end
Near(f_sphere(3, 4, 0, 1), 4, "f_sphere")
Near(f_r(1, 2, 2), 3, "f_r")
Near(f_th(1, 0, 0), pi / 2, "f_th from +z towards +x")
Near(f_th(0, 5, 1), 0, "f_th on +z")
Near(f_ph(0, 1, 0), 0, "f_ph on +y")
Near(f_ph(1, 0, 1), pi / 2, "f_ph at the equator")
Near(f_torus(3, 0, 0, 2, 0.5), 0.5, "f_torus outside")
Near(f_torus(0, 1, 0, 2, 0.5), sqrt(5) - 0.5, "f_torus on the axis")
Near(f_rounded_box(2, 0, 0, 0.1, 1, 1, 1), 1, "f_rounded_box before a face")
Near(f_rounded_box(1.5, 1.5, 0, 0.1, 1, 1, 1), sqrt(0.72) - 0.1, "f_rounded_box by an edge")
Near(f_rounded_box(0, 0, 0, 0.1, 1, 2, 3), -1, "f_rounded_box inside")
Near(f_rounded_box(0, 0, 3.5, 0.1, 1, 2, 3), 0.5, "f_rounded_box's z size")
Near(f_ellipsoid(2, 0, 0, 0.5, 1, 1), 1, "f_ellipsoid")
Near(f_superellipsoid(0, 0.6, 0.8, 1, 1), 0, "f_superellipsoid with exponents 1 is the sphere")
Near(f_superellipsoid(0.5, 0.5, 0, 0.5, 1), 1 - pow(pow(0.5, 4) * 2, 0.5), "f_superellipsoid")
Near(f_paraboloid(1, 2, 1, 3), 0, "f_paraboloid on its surface")
Near(f_paraboloid(0, 1, 0, 2), 2, "f_paraboloid inside")
Near(f_snoise3d(0.3, 0.7, 1.1), 2 * f_noise3d(0.3, 0.7, 1.1) - 1, "f_snoise3d")
#if (f_noise3d(0.3, 0.7, 1.1) < 0 | f_noise3d(0.3, 0.7, 1.1) > 1) #error "noise in [0, 1]" #end
Near(f_noise3d(0.3, 0.7, 1.1), f_bozo(0.3, 0.7, 1.1), "f_bozo")
Near(f_dents(0.3, 0.7, 1.1), pow(f_noise3d(0.3, 0.7, 1.1), 3), "f_dents")
Near(f_gradientX(0.25, 5, 5), 0.25, "f_gradientX")
Near(f_boxed(0.5, -0.25, 0), 0.5, "f_boxed")
Near(f_spherical(0, 0.6, 0.8), 0, "f_spherical")
Near(f_cylindrical(0.6, 9, 0), 0.4, "f_cylindrical")
Near(f_planar(0, -0.25, 7), 0.75, "f_planar")
Near(abs(f_checker(0.5, 0.5, 0.5) - f_checker(1.5, 0.5, 0.5)), 1, "f_checker's cells")
"#)
        .unwrap_or_else(|e| panic!("{e}"));
    }

    #[test]
    fn a_pattern_function_is_moved_by_its_transforms() {
        pov(r#"
#declare G = function { pattern { gradient x scale 2 } }
#if (abs(G(0.5, 0, 0) - 0.25) > 1e-6) #error str(G(0.5, 0, 0), 0, 6) #end
"#)
        .unwrap_or_else(|e| panic!("{e}"));
    }

    #[test]
    fn what_a_function_cannot_be_is_refused_by_name() {
        let cases = [
            ("#declare F = function { internal(3) }", "`internal(3)` is not built in"),
            ("#declare F = function { x }\n#declare V = F(1, 2);", "takes 3 arguments, not 2"),
            ("#declare F = function { <x, y, z> }", "a function computes numbers"),
            ("#declare F = function(a) { x }", "`x` is not a parameter"),
            ("#declare F = function { x + Nothing }", "Nothing"),
            ("#declare F = function(a, a) { a }", "named twice"),
            ("#declare F = function { x }\n#declare G = function { F + 1 }", "call it as"),
        ];
        for (text, expected) in cases {
            let message = pov(text).err().unwrap_or_else(|| panic!("{text} is refused"));
            assert!(message.contains(expected), "{text}: {message}");
        }
        let scn = crate::lang::parse_scene(Path::new("f.scn"), "#declare F = function { x }");
        assert!(scn.is_err(), "POV-Ray's, not the .scn language's");
    }
}
