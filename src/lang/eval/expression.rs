//! Expressions to values: operators (POV-Ray's, with its tolerance on `=`, `!=`, `<=`, `>=`),
//! functions, components, indices, macro calls as values, and random streams.

use std::sync::Arc;

use glam::{DMat3, DVec3, Vec3};

use super::{Body, EPSILON, Evaluator, as_float, as_vector, element_index};
use crate::diagnostic::{SceneError, Span};
use crate::function::{GRAY, component};
use crate::lang::keywords::{Constant, Function};
use crate::lang::syntax::{
    BinaryOp, Colour, Declare, Declared, Expr, ExprKind, Ident, PovColourKind, UnaryOp,
};
use crate::lang::value::{Array, MAX_STRING_BYTES, Value};

impl Evaluator {
    /// Evaluates an expression; a result that is not finite is an error at the expression.
    pub(super) fn value(&mut self, expr: &Expr) -> Result<Value, SceneError> {
        let value = self.eval(expr)?;
        let finite = match &value {
            Value::Float(f) => f.is_finite(),
            Value::Vector(v) => v.is_finite(),
            Value::Numbers(n) => n.iter().all(|f| f.is_finite()),
            Value::String(_)
            | Value::Array(_)
            | Value::Stream(_)
            | Value::Macro(_)
            | Value::Material(_)
            | Value::Object(_)
            | Value::Texture(_)
            | Value::Pigment(_)
            | Value::Finish(_)
            | Value::Look(_)
            | Value::Interior(_)
            | Value::Normal(_)
            | Value::Media(_)
            | Value::ColorMap(_)
            | Value::Camera(_)
            | Value::Sky(_)
            | Value::Light(_)
            | Value::Function(_)
            | Value::File(_)
            | Value::ColourFunction(_)
            | Value::Transform(_)
            | Value::TransformFunction(_) => true,
        };
        if !finite {
            return Err(SceneError::at(
                &expr.span,
                "this expression's value is not a finite number",
            ));
        }
        Ok(value)
    }

    /// A number as the renderer holds it (f32): one out of its range is an error here.
    pub(super) fn single(&mut self, expr: &Expr) -> Result<f32, SceneError> {
        single(self.float(expr)?, &expr.span)
    }

    pub(super) fn float(&mut self, expr: &Expr) -> Result<f64, SceneError> {
        as_float(&self.value(expr)?, &expr.span, "this value")
    }

    /// A number where `what` needs one.
    pub(super) fn number(&mut self, expr: &Expr, what: &str) -> Result<f64, SceneError> {
        as_float(&self.value(expr)?, &expr.span, what)
    }

    pub(super) fn vector(&mut self, expr: &Expr) -> Result<DVec3, SceneError> {
        as_vector(&self.value(expr)?, &expr.span, "this value")
    }

    /// A vector where POV-Ray promotes a 2-vector to one with z 0 (`translate <1, 2>`, a
    /// text's offset `<0, 0>`); `.scn` takes three components.
    pub(super) fn promoted_vector(&mut self, expr: &Expr, what: &str) -> Result<DVec3, SceneError> {
        match (self.value(expr)?, self.dialect) {
            (Value::Numbers(n), crate::lang::dialect::Dialect::Pov) if n.len() == 2 => {
                Ok(DVec3::new(n[0], n[1], 0.0))
            }
            (value, _) => as_vector(&value, &expr.span, what),
        }
    }

    pub(super) fn vec3(&mut self, expr: &Expr) -> Result<Vec3, SceneError> {
        single_vector(self.vector(expr)?, &expr.span)
    }

    /// A vector, or a number promoted to one with three equal components (POV-Ray's promotion
    /// where a vector is expected: `turbulence 0.5`, `brick_size 2`).
    pub(super) fn splat_vec3(&mut self, expr: &Expr) -> Result<Vec3, SceneError> {
        match self.value(expr)? {
            Value::Float(f) => Ok(Vec3::splat(single(f, &expr.span)?)),
            _ => self.vec3(expr),
        }
    }

    pub(super) fn nonzero(&mut self, expr: &Expr, what: &str) -> Result<Vec3, SceneError> {
        let v = self.vec3(expr)?;
        if v.length() == 0.0 {
            return Err(SceneError::at(&expr.span, format!("{what} is a zero vector")));
        }
        Ok(v)
    }

    pub(super) fn positive(&mut self, expr: &Expr, what: &str) -> Result<f32, SceneError> {
        let f = self.float(expr)?;
        if f <= 0.0 {
            let sign = if f < 0.0 { "negative" } else { "zero" };
            return Err(SceneError::at(
                &expr.span,
                format!("{what} {f} is {sign}: it must be positive"),
            ));
        }
        single(f, &expr.span)
    }

    /// A material's `roughness`: GGX alpha, in [0, 1] (`docs/language.md`, Materials).
    pub(super) fn roughness(&mut self, expr: &Expr) -> Result<f32, SceneError> {
        let alpha = self.float(expr)?;
        if !(0.0..=1.0).contains(&alpha) {
            return Err(SceneError::at(
                &expr.span,
                format!("roughness {alpha} must be between 0 and 1 (GGX alpha)"),
            ));
        }
        single(alpha, &expr.span)
    }

    /// `coat`: the share of the coat's reflection kept, 0 (none) to 1.
    pub(super) fn coat(&mut self, expr: &Expr) -> Result<f32, SceneError> {
        let strength = self.float(expr)?;
        if !(0.0..=1.0).contains(&strength) {
            return Err(SceneError::at(
                &expr.span,
                format!("coat {strength} must be between 0 (no coat) and 1 (a physical coat)"),
            ));
        }
        single(strength, &expr.span)
    }

    /// `coat_roughness`: the coat's GGX alpha, above 0 (a coat is glossy) and at most 1.
    pub(super) fn coat_roughness(&mut self, expr: &Expr) -> Result<f32, SceneError> {
        let alpha = self.float(expr)?;
        if !(alpha > 0.0 && alpha <= 1.0) {
            return Err(SceneError::at(
                &expr.span,
                format!("coat_roughness {alpha} must be above 0 and at most 1 (GGX alpha)"),
            ));
        }
        single(alpha, &expr.span)
    }

    pub(super) fn integer(&mut self, expr: &Expr, min: u64, max: u64) -> Result<u64, SceneError> {
        let f = self.float(expr)?;
        if f.fract() != 0.0 || f < min as f64 || f > max as f64 {
            return Err(SceneError::at(
                &expr.span,
                format!("{f} is not a whole number from {min} to {max}"),
            ));
        }
        Ok(f as u64)
    }

    /// A whole number from `min` to `max` for the setting `name`.
    pub(super) fn setting_integer(
        &mut self,
        expr: &Expr,
        name: &str,
        min: u64,
        max: u64,
    ) -> Result<u64, SceneError> {
        let f = self.float(expr)?;
        if f.fract() != 0.0 || f < min as f64 || f > max as f64 {
            return Err(SceneError::at(
                &expr.span,
                format!(
                    "`{name}` {f} is out of range: it must be a whole number from {min} to {max}"
                ),
            ));
        }
        Ok(f as u64)
    }

    /// A string where `what` needs one (a file name, a message).
    pub(super) fn string(&mut self, expr: &Expr, what: &str) -> Result<String, SceneError> {
        self.text(expr, what).map(|s| s.to_string())
    }

    /// A string where `what` needs one, shared with where it came from.
    pub(super) fn text(&mut self, expr: &Expr, what: &str) -> Result<Arc<String>, SceneError> {
        text_of(self.value(expr)?, expr, what)
    }

    /// `#declare S = concat(S, ...)` (or `#local`): appends to the string S holds, in place where
    /// no other variable shares it, so that a loop of appends takes time linear in the length
    /// made. False (nothing evaluated) where the declaration is not such an append.
    pub(super) fn append_in_place(&mut self, declare: &Declare) -> Result<bool, SceneError> {
        let Declare { local, name, indices, value, .. } = declare;
        let Declared::Value(Expr { kind: ExprKind::Function(Function::Concat, args), span }) =
            value
        else {
            return Ok(false);
        };
        let Some(ExprKind::Ident(first)) = args.first().map(|a| &a.kind) else {
            return Ok(false);
        };
        let before = match self.slot_mut(&name.name, *local) {
            Some(Value::String(s)) if *first == name.name && indices.is_empty() => s.clone(),
            _ => return Ok(false),
        };
        let mut parts = Vec::with_capacity(args.len() - 1);
        for arg in &args[1..] {
            parts.push(self.text(arg, "`concat`")?);
        }
        let text = match self.slot_mut(&name.name, *local) {
            Some(Value::String(s)) if Arc::ptr_eq(s, &before) => {
                drop(before);
                return append(Arc::make_mut(s), &parts, span).map(|()| true);
            }
            // A macro among the parts changed S: the value read first is the one concatenated.
            _ => {
                let mut text = before.to_string();
                append(&mut text, &parts, span)?;
                text
            }
        };
        self.bind(&name.name, Value::String(Arc::new(text)), *local);
        Ok(true)
    }

    /// A colour: `rgb <r, g, b>`, `rgb s`, or an expression; components must not be negative.
    pub(super) fn colour(&mut self, colour: &Colour) -> Result<Vec3, SceneError> {
        let at = &colour.span;
        let value = match &colour.value.kind {
            // `rgb e` is checked here, where the colour is written.
            ExprKind::Rgb(inner) => self.value(inner)?,
            _ => self.value(&colour.value)?,
        };
        colour_of(value, at)
    }

    /// A colour as `colour` reads it, negative components kept (for the caller to refuse or
    /// warn about with its own reason).
    pub(super) fn signed_colour(&mut self, colour: &Colour) -> Result<Vec3, SceneError> {
        let at = &colour.span;
        let value = match &colour.value.kind {
            ExprKind::Rgb(inner) => self.value(inner)?,
            _ => self.value(&colour.value)?,
        };
        match value {
            Value::Float(f) => Ok(Vec3::splat(single(f, at)?)),
            Value::Vector(v) => single_vector(v, at),
            other => Err(SceneError::at(at, format!("expected a colour, found {}", other.kind()))),
        }
    }

    fn eval(&mut self, expr: &Expr) -> Result<Value, SceneError> {
        let at = &expr.span;
        Ok(match &expr.kind {
            ExprKind::Number(f) => Value::Float(*f),
            ExprKind::String(s) => Value::String(Arc::new(s.clone())),
            ExprKind::Constant(c) => match c {
                Constant::Pi => Value::Float(std::f64::consts::PI),
                Constant::X => Value::Vector(DVec3::X),
                Constant::Y => Value::Vector(DVec3::Y),
                Constant::Z => Value::Vector(DVec3::Z),
                Constant::True => Value::Float(1.0),
                Constant::False => Value::Float(0.0),
                Constant::Clock => Value::Float(self.frame.clock),
                Constant::FrameNumber => Value::Float(f64::from(self.frame.number)),
                Constant::ClockOn => Value::Float(f64::from(u8::from(self.frame.step.is_some()))),
                Constant::ClockDelta => Value::Float(self.frame.step.unwrap_or(0.0)),
            },
            ExprKind::Ident(name) => match self.lookup(name) {
                Some(v) => v.clone(),
                None => {
                    let ident = crate::lang::syntax::Ident { name: name.clone(), span: at.clone() };
                    return Err(self.unknown(&ident));
                }
            },
            ExprKind::Vector(components) => {
                let mut numbers = Vec::with_capacity(components.len());
                for component in components {
                    match self.eval(component)? {
                        Value::Float(f) => numbers.push(f),
                        other => {
                            return Err(SceneError::at(
                                &component.span,
                                format!("a vector's components are numbers, not {}", other.kind()),
                            ));
                        }
                    }
                }
                match numbers.as_slice() {
                    [x, y, z] => Value::Vector(DVec3::new(*x, *y, *z)),
                    _ => Value::Numbers(numbers),
                }
            }
            ExprKind::Rgb(inner) => {
                let colour = match self.eval(inner)? {
                    Value::Float(f) => DVec3::splat(f),
                    Value::Vector(v) => v,
                    other => {
                        return Err(SceneError::at(
                            at,
                            format!("expected a colour, found {}", other.kind()),
                        ));
                    }
                };
                // POV-Ray's colours may be negative as values (`rgb -1` in colour arithmetic);
                // where a surface takes one it is clamped (`Evaluator::pov_colour`).
                if self.dialect == crate::lang::dialect::Dialect::Scn {
                    check_colour(colour, at)?;
                }
                Value::Vector(colour)
            }
            ExprKind::PovColour(kind, inner) => pov_colour_value(*kind, self.eval(inner)?, at)?,
            ExprKind::ColourParts { base, parts } => {
                let mut colour = match base {
                    None => [0.0; 5],
                    Some(base) => colour_components(self.eval(base)?, &base.span)?,
                };
                for (channel, value) in parts {
                    colour[*channel as usize] = self.number(value, "a colour's component")?;
                }
                match colour {
                    [r, g, b, 0.0, 0.0] => Value::Vector(DVec3::new(r, g, b)),
                    _ => Value::Numbers(colour.to_vec()),
                }
            }
            ExprKind::Unary { op, operand } => {
                let v = self.eval(operand)?;
                match op {
                    UnaryOp::Plus => v,
                    UnaryOp::Negate => arithmetic(at, "-", Value::Float(-1.0), v, |a, b| a * b)?,
                    UnaryOp::Not => Value::Float(truth(as_float(&v, &operand.span, "`!`")? == 0.0)),
                }
            }
            ExprKind::Binary { op, op_span, left, right } => {
                let a = self.eval(left)?;
                // `&` and `|` read both sides, as POV-Ray does.
                let b = self.eval(right)?;
                binary(*op, op_span, a, b)?
            }
            ExprKind::Ternary { condition, then, otherwise } => {
                if self.number(condition, "`?`'s condition")? != 0.0 {
                    self.eval(then)?
                } else {
                    self.eval(otherwise)?
                }
            }
            ExprKind::Component { value, axis, span } => match self.eval(value)? {
                Value::Vector(v) if *axis == GRAY => {
                    Value::Float(component(&[v.x, v.y, v.z, 0.0, 0.0], GRAY))
                }
                Value::Numbers(n) if *axis == GRAY && n.len() >= 3 => {
                    Value::Float(component(&[n[0], n[1], n[2], 0.0, 0.0], GRAY))
                }
                Value::Vector(v) if *axis < 3 => Value::Float(v[*axis]),
                // A colour without filter and transmit has them 0, as in POV-Ray.
                Value::Vector(_) => Value::Float(0.0),
                Value::Numbers(n) if *axis < n.len() => Value::Float(n[*axis]),
                Value::Numbers(n) if n.len() == 4 && *axis == 4 => Value::Float(0.0),
                // A number is the grey colour of that value.
                Value::Float(f) if *axis == GRAY => Value::Float(f),
                other if *axis == GRAY => {
                    return Err(SceneError::at(span, format!("{} has no `.gray`", other.kind())));
                }
                other => {
                    return Err(SceneError::at(
                        span,
                        format!("{} has no component {}", other.kind(), axis + 1),
                    ));
                }
            },
            ExprKind::Index { .. } => self.index(expr)?,
            ExprKind::Block(declared) => self.declared(declared, None)?,
            ExprKind::Function(f, args) => self.function(*f, args, at)?,
            ExprKind::Call(call) => {
                match self.lookup(&call.name.name) {
                    Some(Value::Function(f)) => {
                        let f = f.clone();
                        return self.call_function(&f, call);
                    }
                    Some(Value::ColourFunction(f)) => {
                        let f = f.clone();
                        return self.call_colour_function(&f, call);
                    }
                    Some(Value::TransformFunction(f)) => {
                        let f = f.clone();
                        return self.call_transform_function(&f, call);
                    }
                    _ => {}
                }
                let mut slot = None;
                self.call_macro(call, &mut Body::Value(&mut slot))?;
                slot.ok_or_else(|| {
                    SceneError::at(
                        &call.span,
                        format!("macro `{}` gives no value where one is expected", call.name.name),
                    )
                })?
            }
        })
    }

    /// `A[i]...[k]`: all the indices of one array at once.
    fn index(&mut self, expr: &Expr) -> Result<Value, SceneError> {
        let mut indices = Vec::new();
        let mut base = expr;
        while let ExprKind::Index { array, index } = &base.kind {
            indices.push(index.as_ref());
            base = array;
        }
        indices.reverse();
        let array = match self.eval(base)? {
            Value::Array(a) => a,
            other => {
                return Err(SceneError::at(
                    &indices[0].span,
                    format!("only an array takes an index, not {}", other.kind()),
                ));
            }
        };
        let mut at = Vec::new();
        for index in indices {
            at.push((self.number(index, "an index")?, index.span.clone()));
        }
        let name = match &base.kind {
            ExprKind::Ident(name) => Some(name.as_str()),
            _ => None,
        };
        let flat = element_index(&array, name, &at)?;
        array.get(flat).cloned().ok_or_else(|| {
            let shown: String = at.iter().map(|(i, _)| format!("[{i}]")).collect();
            let element = format!("{}{shown}", name.unwrap_or("the array"));
            SceneError::at(
                &at[0].1,
                format!("`{element}` is not set (the array was declared without it)"),
            )
        })
    }

    /// The array `f` takes as its argument `arg`.
    fn array_argument(&mut self, f: Function, arg: &Expr) -> Result<Arc<Array>, SceneError> {
        match self.value(arg)? {
            Value::Array(a) => Ok(a),
            other => Err(SceneError::at(
                &arg.span,
                format!("`{}` takes an array, not {}", f.name(), other.kind()),
            )),
        }
    }

    fn function(&mut self, f: Function, args: &[Expr], at: &Span) -> Result<Value, SceneError> {
        let name = f.name();
        let number = |this: &mut Self, i: usize| -> Result<f64, SceneError> {
            match this.value(&args[i])? {
                Value::Float(x) => Ok(x),
                other => Err(SceneError::at(
                    &args[i].span,
                    format!("`{name}` takes numbers, not {}", other.kind()),
                )),
            }
        };
        let vector = |this: &mut Self, i: usize| -> Result<DVec3, SceneError> {
            as_vector(&this.value(&args[i])?, &args[i].span, &format!("`{name}`"))
        };
        let domain = |ok: bool, x: f64, what: &str| {
            if ok { Ok(()) } else { Err(SceneError::at(at, format!("`{name}` of {x}: {what}"))) }
        };
        use Function::*;
        Ok(match f {
            Sin | Cos | Tan | Asin | Acos | Atan | Sinh | Cosh | Tanh | Asinh | Acosh | Atanh
            | Sqrt | Sqr | Abs | Radians | Degrees | Floor | Ceil | Int | Exp | Ln | Log => {
                let x = number(self, 0)?;
                Value::Float(match f {
                    Sin => x.sin(),
                    Cos => x.cos(),
                    Tan => x.tan(),
                    Asin => {
                        domain((-1.0..=1.0).contains(&x), x, "outside [-1, 1]").map(|_| x.asin())?
                    }
                    Acos => {
                        domain((-1.0..=1.0).contains(&x), x, "outside [-1, 1]").map(|_| x.acos())?
                    }
                    Atan => x.atan(),
                    Sinh => x.sinh(),
                    Cosh => x.cosh(),
                    Tanh => x.tanh(),
                    Asinh => x.asinh(),
                    Acosh => domain(x >= 1.0, x, "below 1").map(|_| x.acosh())?,
                    Atanh => domain(x.abs() < 1.0, x, "outside (-1, 1)").map(|_| x.atanh())?,
                    Sqrt => domain(x >= 0.0, x, "negative").map(|_| x.sqrt())?,
                    Sqr => x * x,
                    Abs => x.abs(),
                    Radians => x.to_radians(),
                    Degrees => x.to_degrees(),
                    Floor => x.floor(),
                    Ceil => x.ceil(),
                    Int => x.trunc(),
                    Exp => x.exp(),
                    Ln => domain(x > 0.0, x, "not positive").map(|_| x.ln())?,
                    Log => domain(x > 0.0, x, "not positive").map(|_| x.log10())?,
                    _ => unreachable!("a function of one number"),
                })
            }
            Pow | Min | Max | Mod | Div | Atan2 => {
                let (x, y) = (number(self, 0)?, number(self, 1)?);
                Value::Float(match f {
                    Pow => x.powf(y),
                    Min => x.min(y),
                    Max => x.max(y),
                    Atan2 => x.atan2(y),
                    // The sign of x, as C's fmod and POV-Ray's mod.
                    Mod => {
                        if y == 0.0 {
                            return Err(SceneError::at(at, "`mod` by zero"));
                        }
                        x % y
                    }
                    Div => {
                        if y == 0.0 {
                            return Err(SceneError::at(at, "`div` by zero"));
                        }
                        (x / y).trunc()
                    }
                    _ => unreachable!("a function of two numbers"),
                })
            }
            Vlength => Value::Float(vector(self, 0)?.length()),
            Vnormalize => {
                let v = vector(self, 0)?;
                if v.length() == 0.0 {
                    return Err(SceneError::at(at, "`vnormalize` of a zero vector"));
                }
                Value::Vector(v / v.length())
            }
            Vdot => Value::Float(vector(self, 0)?.dot(vector(self, 1)?)),
            Vcross => Value::Vector(vector(self, 0)?.cross(vector(self, 1)?)),
            Vrotate => {
                let (v, degrees) = (vector(self, 0)?, vector(self, 1)?);
                let r = degrees * (std::f64::consts::PI / 180.0);
                // As `rotate`: about x, then y, then z.
                let m = DMat3::from_rotation_z(r.z)
                    * DMat3::from_rotation_y(r.y)
                    * DMat3::from_rotation_x(r.x);
                Value::Vector(m * v)
            }
            Select => {
                let a = number(self, 0)?;
                if a < 0.0 { self.value(&args[1])? } else { self.value(&args[2])? }
            }
            Seed => {
                let n = number(self, 0)?;
                self.streams.push(seed_state(n));
                Value::Stream(self.streams.len() - 1)
            }
            Rand => match self.value(&args[0])? {
                Value::Stream(s) => Value::Float(next_random(&mut self.streams[s])),
                other => {
                    return Err(SceneError::at(
                        &args[0].span,
                        format!("`rand` takes a stream made by `seed(n)`, not {}", other.kind()),
                    ));
                }
            },
            Concat => {
                let mut text = String::new();
                for arg in args {
                    let part = self.text(arg, "`concat`")?;
                    append(&mut text, &[part], at)?;
                }
                Value::String(Arc::new(text))
            }
            Str => {
                let x = number(self, 0)?;
                let width = number(self, 1)?;
                let decimals = number(self, 2)?;
                Value::String(Arc::new(format_number(x, width, decimals)))
            }
            Dimensions => Value::Float(self.array_argument(f, &args[0])?.dimensions.len() as f64),
            DimensionSize => {
                let array = self.array_argument(f, &args[0])?;
                let n = number(self, 1)?;
                let count = array.dimensions.len();
                if n.fract() != 0.0 || n < 1.0 || n > count as f64 {
                    return Err(SceneError::at(
                        &args[1].span,
                        format!("the array has dimensions 1 to {count}, not {n}"),
                    ));
                }
                Value::Float(array.dimensions[n as usize - 1] as f64)
            }
            VaxisRotate => {
                let (v, axis, degrees) = (vector(self, 0)?, vector(self, 1)?, number(self, 2)?);
                if axis.length() == 0.0 {
                    return Err(SceneError::at(&args[1].span, "`vaxis_rotate` about a zero axis"));
                }
                // The same turn as `rotate` about a coordinate axis (`rotate 30*x` is
                // `vaxis_rotate(v, x, 30)`).
                Value::Vector(DMat3::from_axis_angle(axis.normalize(), degrees.to_radians()) * v)
            }
            Vturbulence => {
                let (lambda, omega, octaves) =
                    (number(self, 0)?, number(self, 1)?, number(self, 2)?);
                let at = &args[3].span;
                let point = single_vector(vector(self, 3)?, at)?;
                let octaves = crate::texture::Octaves {
                    // A count, held to 1..=16 as a pattern's `octaves` is.
                    octaves: octaves.clamp(1.0, 16.0) as u32,
                    omega: single(omega, &args[1].span)?,
                    lambda: single(lambda, &args[0].span)?,
                };
                Value::Vector(octaves.vector(point).as_dvec3())
            }
            Strlen => Value::Float(self.text(&args[0], "`strlen`")?.chars().count() as f64),
            Strupr => Value::String(Arc::new(self.text(&args[0], "`strupr`")?.to_uppercase())),
            Strlwr => Value::String(Arc::new(self.text(&args[0], "`strlwr`")?.to_lowercase())),
            Substr => {
                let text = self.text(&args[0], "`substr`")?;
                let (start, length) = (number(self, 1)?, number(self, 2)?);
                let count = text.chars().count() as f64;
                if start < 1.0 || length < 0.0 || start + length - 1.0 > count {
                    return Err(SceneError::at(
                        at,
                        format!(
                            "`substr` of {length} characters from {start} of a string of                              {count}: the characters are 1 to {count}"
                        ),
                    ));
                }
                let part = text.chars().skip(start as usize - 1).take(length as usize);
                Value::String(Arc::new(part.collect()))
            }
            Chr => {
                let code = number(self, 0)?;
                let c = (code.fract() == 0.0 && (1.0..=f64::from(u32::MAX)).contains(&code))
                    .then(|| char::from_u32(code as u32))
                    .flatten()
                    .ok_or_else(|| {
                        SceneError::at(&args[0].span, format!("`chr` of {code}: no character"))
                    })?;
                Value::String(Arc::new(c.to_string()))
            }
            Asc => {
                let text = self.text(&args[0], "`asc`")?;
                Value::Float(text.chars().next().map_or(0.0, |c| f64::from(u32::from(c))))
            }
            Val => Value::Float(leading_number(&self.text(&args[0], "`val`")?)),
            Vstr => {
                let count = number(self, 0)?;
                let v = vector(self, 1)?;
                let separator = self.text(&args[2], "`vstr`")?;
                let (width, decimals) = (number(self, 3)?, number(self, 4)?);
                if !(1.0..=3.0).contains(&count) || count.fract() != 0.0 {
                    return Err(SceneError::at(
                        &args[0].span,
                        format!("`vstr` of {count} components: a vector has 1 to 3"),
                    ));
                }
                let parts: Vec<String> = v.to_array()[..count as usize]
                    .iter()
                    .map(|&c| format_number(c, width, decimals))
                    .collect();
                Value::String(Arc::new(parts.join(separator.as_str())))
            }
            FileExists => {
                let name = self.text(&args[0], "`file_exists`")?;
                let (path, built_in) = self.find_include(&at.file.path, &name);
                Value::Float(if built_in.is_some() || path.is_file() { 1.0 } else { 0.0 })
            }
            Defined => {
                // A name, or an array's element (`defined(A[i])`).
                let mut indices = Vec::new();
                let mut base = &args[0];
                while let ExprKind::Index { array, index } = &base.kind {
                    indices.push(index.as_ref().clone());
                    base = array;
                }
                indices.reverse();
                let ExprKind::Ident(name) = &base.kind else {
                    return Err(SceneError::at(&args[0].span, "`defined` takes a name"));
                };
                let name = Ident { name: name.clone(), span: base.span.clone() };
                Value::Float(if self.is_set(&name, &indices)? { 1.0 } else { 0.0 })
            }
            MinExtent => self.extent(&args[0], false)?,
            MaxExtent => self.extent(&args[0], true)?,
            Trace => self.trace(args)?,
            Inside => self.inside(args)?,
        })
    }
}

/// C's `atof`, as POV-Ray's `val`: the number the string starts with (after blanks), 0 if none.
fn leading_number(text: &str) -> f64 {
    let text = text.trim_start();
    // No number is written in more than 64 bytes: a long string costs no more.
    let end = (0..=text.len().min(64)).rev().find(|&i| text.is_char_boundary(i)).unwrap_or(0);
    let text = &text[..end];
    (1..=text.len())
        .rev()
        .filter(|&end| text.is_char_boundary(end))
        .find_map(|end| text[..end].parse::<f64>().ok().filter(|x| x.is_finite()))
        .unwrap_or(0.0)
}

/// Appends `parts` to `text`, within the bound on a string's length (an error at `at`).
fn append(text: &mut String, parts: &[Arc<String>], at: &Span) -> Result<(), SceneError> {
    let length = text.len() + parts.iter().map(|p| p.len()).sum::<usize>();
    if length > MAX_STRING_BYTES {
        return Err(SceneError::at(
            at,
            format!("a string of {length} bytes: at most {MAX_STRING_BYTES} are allowed"),
        ));
    }
    parts.iter().for_each(|p| text.push_str(p));
    Ok(())
}

/// `str(value, width, decimals)`: at least |width| characters, padded with zeros on the left
/// (`str(7, 3, 0)` is `007`, as the language's contract says; POV-Ray pads a positive width with
/// blanks and only a negative one with zeros); `decimals` digits after the point, or six when
/// negative (POV-Ray's `%f`).
fn format_number(x: f64, width: f64, decimals: f64) -> String {
    let width = width.abs().min(1000.0) as usize;
    let decimals = if decimals < 0.0 { 6 } else { decimals.min(64.0) as usize };
    format!("{x:0width$.decimals$}")
}

/// A stream's state from `seed(n)`: n's integer part as a 32-bit word, as POV-Ray 3.7 seeds it.
fn seed_state(n: f64) -> u32 {
    n.trunc() as i32 as u32
}

/// The next number of a stream: POV-Ray 3.7's generator (the linear congruential step
/// `next = next * 1812433253 + 12345` modulo 2^32), so that a scene draws the same numbers as in
/// POV-Ray; divided by 2^32 where POV-Ray divides by 2^32 - 1, so that every value is below 1
/// (they differ by at most 2.4e-10).
fn next_random(state: &mut u32) -> f64 {
    *state = state.wrapping_mul(1_812_433_253).wrapping_add(12_345);
    f64::from(*state) / 4_294_967_296.0
}

/// `rgbf`, `rgbt`, `rgbft` (as `<r, g, b, filter, transmit>`) or `srgb` (as linear `<r, g, b>`):
/// a number stands for every component written.
fn pov_colour_value(kind: PovColourKind, value: Value, at: &Span) -> Result<Value, SceneError> {
    let written = match kind {
        PovColourKind::Rgbf | PovColourKind::Rgbt => 4,
        PovColourKind::Rgbft => 5,
        PovColourKind::Srgb => 3,
    };
    let numbers = match value {
        Value::Float(f) => vec![f; written],
        Value::Vector(v) if written == 3 => v.to_array().to_vec(),
        Value::Numbers(n) if n.len() == written => n,
        other => {
            return Err(SceneError::at(
                at,
                format!("this colour needs {written} components, not {}", other.kind()),
            ));
        }
    };
    Ok(match kind {
        PovColourKind::Rgbf => {
            Value::Numbers(vec![numbers[0], numbers[1], numbers[2], numbers[3], 0.0])
        }
        PovColourKind::Rgbt => {
            Value::Numbers(vec![numbers[0], numbers[1], numbers[2], 0.0, numbers[3]])
        }
        PovColourKind::Rgbft => Value::Numbers(numbers),
        PovColourKind::Srgb => {
            // sRGB's decoding of each component to linear light.
            let linear = |c: f64| {
                if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
            };
            Value::Vector(DVec3::new(linear(numbers[0]), linear(numbers[1]), linear(numbers[2])))
        }
    })
}

/// A POV-Ray colour's `<red, green, blue, filter, transmit>`: a number is grey, a vector has no
/// filter or transmit, four numbers are `rgbf`.
fn colour_components(value: Value, at: &Span) -> Result<[f64; 5], SceneError> {
    Ok(match value {
        Value::Float(f) => [f, f, f, 0.0, 0.0],
        Value::Vector(v) => [v.x, v.y, v.z, 0.0, 0.0],
        Value::Numbers(n) if n.len() == 4 => [n[0], n[1], n[2], n[3], 0.0],
        Value::Numbers(n) if n.len() == 5 => [n[0], n[1], n[2], n[3], n[4]],
        other => {
            return Err(SceneError::at(at, format!("expected a colour, found {}", other.kind())));
        }
    })
}

/// A value where a colour is expected: a number (grey) or a vector, not negative.
pub(super) fn colour_of(value: Value, at: &Span) -> Result<Vec3, SceneError> {
    let colour = match value {
        Value::Float(f) => DVec3::splat(f),
        Value::Vector(v) => v,
        other => {
            return Err(SceneError::at(at, format!("expected a colour, found {}", other.kind())));
        }
    };
    check_colour(colour, at)?;
    Ok(Vec3::new(single(colour.x, at)?, single(colour.y, at)?, single(colour.z, at)?))
}

fn check_colour(colour: DVec3, at: &Span) -> Result<(), SceneError> {
    if colour.min_element() < 0.0 {
        let [r, g, b] = colour.to_array();
        return Err(SceneError::at(at, format!("colour <{r}, {g}, {b}> has a negative component")));
    }
    Ok(())
}

fn truth(b: bool) -> f64 {
    if b { 1.0 } else { 0.0 }
}

fn binary(op: BinaryOp, at: &Span, a: Value, b: Value) -> Result<Value, SceneError> {
    let symbol = op.symbol();
    match op {
        BinaryOp::Add => arithmetic(at, symbol, a, b, |x, y| x + y),
        BinaryOp::Subtract => arithmetic(at, symbol, a, b, |x, y| x - y),
        BinaryOp::Multiply => arithmetic(at, symbol, a, b, |x, y| x * y),
        BinaryOp::Divide => {
            let divisor_zero = match &b {
                Value::Float(f) => *f == 0.0,
                Value::Vector(v) => v.cmpeq(DVec3::ZERO).any(),
                _ => false,
            };
            if divisor_zero {
                return Err(SceneError::at(at, "division by zero"));
            }
            arithmetic(at, symbol, a, b, |x, y| x / y)
        }
        BinaryOp::Or
        | BinaryOp::And
        | BinaryOp::Less
        | BinaryOp::LessEqual
        | BinaryOp::Greater
        | BinaryOp::GreaterEqual
        | BinaryOp::Equal
        | BinaryOp::NotEqual => {
            let (x, y) = match (&a, &b) {
                (Value::Float(x), Value::Float(y)) => (*x, *y),
                _ => {
                    return Err(SceneError::at(
                        at,
                        format!("`{symbol}` compares numbers, not {} and {}", a.kind(), b.kind()),
                    ));
                }
            };
            Ok(Value::Float(truth(match op {
                BinaryOp::Or => x != 0.0 || y != 0.0,
                BinaryOp::And => x != 0.0 && y != 0.0,
                BinaryOp::Less => x < y,
                BinaryOp::Greater => x > y,
                BinaryOp::LessEqual => x - y <= EPSILON,
                BinaryOp::GreaterEqual => y - x <= EPSILON,
                BinaryOp::Equal => (x - y).abs() <= EPSILON,
                BinaryOp::NotEqual => (x - y).abs() > EPSILON,
                BinaryOp::Add | BinaryOp::Subtract | BinaryOp::Multiply | BinaryOp::Divide => {
                    unreachable!("arithmetic is handled above")
                }
            })))
        }
    }
}

/// `+ - * /` on numbers and vectors: a number meets a vector component-wise (promotion); so do
/// lists of numbers of one length (POV-Ray's colours with filter and transmit, which a vector
/// meets as a colour without them).
fn arithmetic(
    at: &Span,
    symbol: &str,
    a: Value,
    b: Value,
    f: impl Fn(f64, f64) -> f64,
) -> Result<Value, SceneError> {
    let vector = |v: &Value| match v {
        Value::Float(x) => Some(DVec3::splat(*x)),
        Value::Vector(v) => Some(*v),
        _ => None,
    };
    let numbers = |v: &Value, n: usize| match v {
        Value::Float(x) => Some(vec![*x; n]),
        Value::Vector(v) if n == 5 => Some(vec![v.x, v.y, v.z, 0.0, 0.0]),
        Value::Numbers(m) if m.len() == n => Some(m.clone()),
        _ => None,
    };
    let length = match (&a, &b) {
        (Value::Numbers(n), _) | (_, Value::Numbers(n)) => Some(n.len()),
        _ => None,
    };
    if let Some(n) = length
        && let (Some(x), Some(y)) = (numbers(&a, n), numbers(&b, n))
    {
        return Ok(Value::Numbers(x.iter().zip(&y).map(|(x, y)| f(*x, *y)).collect()));
    }
    match (&a, &b) {
        (Value::Float(x), Value::Float(y)) => Ok(Value::Float(f(*x, *y))),
        _ => match (vector(&a), vector(&b)) {
            (Some(x), Some(y)) => {
                Ok(Value::Vector(DVec3::new(f(x.x, y.x), f(x.y, y.y), f(x.z, y.z))))
            }
            _ => Err(SceneError::at(
                at,
                format!("`{symbol}` cannot combine {} and {}", a.kind(), b.kind()),
            )),
        },
    }
}

/// `value` as f32, the precision the renderer computes in: a value that is finite here but would
/// be infinite there (beyond 3.4e38), or that would vanish (non-zero, below 1.2e-38), is an error
/// at `at` rather than a silently black image or a missing object.
pub(super) fn single(value: f64, at: &Span) -> Result<f32, SceneError> {
    let single = value as f32;
    if value.is_finite() && !single.is_finite() {
        return Err(SceneError::at(
            at,
            format!(
                "{value:e} is too large: the renderer computes in 32-bit floats (at most 3.4e38)"
            ),
        ));
    }
    if value != 0.0 && value.abs() < f64::from(f32::MIN_POSITIVE) {
        return Err(SceneError::at(
            at,
            format!(
                "{value:e} is too small: the renderer computes in 32-bit floats, where it would \
                 vanish (the least is 1.2e-38)"
            ),
        ));
    }
    Ok(single)
}

/// A vector as f32, each component checked as `single` does; but a component that vanishes in
/// f32 beside one that does not is rounded to zero, as f32 rounds every component relative to
/// the vector's size (`<x, x*x*x, 0>` with x = -3.9e-14 in float5.pov). A vector whose every
/// non-zero component vanishes is still an error.
pub(super) fn single_vector(v: DVec3, at: &Span) -> Result<Vec3, SceneError> {
    let below = v.abs().cmplt(DVec3::splat(f64::from(f32::MIN_POSITIVE)));
    let vanishing = below & v.cmpne(DVec3::ZERO);
    let v = if below.all() { v } else { DVec3::select(vanishing, DVec3::ZERO, v) };
    Ok(Vec3::new(single(v.x, at)?, single(v.y, at)?, single(v.z, at)?))
}

/// `value`, `expr`'s, as a string where `what` needs one.
pub(super) fn text_of(value: Value, expr: &Expr, what: &str) -> Result<Arc<String>, SceneError> {
    match value {
        Value::String(s) => Ok(s),
        other => {
            Err(SceneError::at(&expr.span, format!("{what} needs a string, not {}", other.kind())))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn str_pads_with_zeros_and_rounds() {
        assert_eq!(format_number(7.0, 3.0, 0.0), "007");
        assert_eq!(format_number(1.23456, 0.0, 2.0), "1.23");
        assert_eq!(format_number(-2.5, 6.0, 1.0), "-002.5");
        assert_eq!(format_number(0.25, 0.0, -1.0), "0.250000");
        assert_eq!(format_number(7.0, -3.0, 0.0), "007");
    }

    #[test]
    fn random_streams_are_uniform_and_reproducible() {
        // POV-Ray's first numbers for seed(0): 12345 / 2^32, then the next step.
        let mut zero = seed_state(0.0);
        assert_eq!(next_random(&mut zero), 12_345.0 / 4_294_967_296.0);
        let second = 12_345u32.wrapping_mul(1_812_433_253).wrapping_add(12_345);
        assert_eq!(next_random(&mut zero), f64::from(second) / 4_294_967_296.0);
        let mut a = seed_state(42.0);
        let mut b = seed_state(42.0);
        let first: Vec<f64> = (0..1000).map(|_| next_random(&mut a)).collect();
        assert!(first.iter().all(|&x| (0.0..1.0).contains(&x)));
        assert_eq!(first, (0..1000).map(|_| next_random(&mut b)).collect::<Vec<_>>());
        let mean = first.iter().sum::<f64>() / 1000.0;
        assert!((mean - 0.5).abs() < 0.05, "{mean}");
        let mut c = seed_state(43.0);
        assert_ne!(first[0], next_random(&mut c));
    }
}
