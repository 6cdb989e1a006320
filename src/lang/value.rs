//! Values bound by `#declare` and produced by expressions, and expression evaluation
//! (f64 throughout; the scene graph takes f32).

use std::collections::HashMap;
use std::sync::{Arc, LazyLock};

use glam::DVec3;
use pest::iterators::Pair;
use pest::pratt_parser::{Assoc, Op, PrattParser};

use super::parser::Rule;
use crate::diagnostic::SceneError;
use crate::scene::graph::{MaterialDesc, ObjectNode, TextureNode};

#[derive(Debug, Clone)]
pub enum Value {
    Float(f64),
    Vector(DVec3),
    /// A vector literal with other than three components (`matrix` takes twelve).
    Numbers(Vec<f64>),
    Material(Arc<MaterialDesc>),
    Object(Arc<ObjectNode>),
    Texture(Arc<TextureNode>),
}

impl Value {
    pub fn kind(&self) -> &'static str {
        match self {
            Value::Float(_) => "a number",
            Value::Vector(_) => "a vector",
            Value::Numbers(n) if n.len() == 2 => "a 2-vector",
            Value::Numbers(_) => "a list of numbers",
            Value::Material(_) => "a material",
            Value::Object(_) => "an object",
            Value::Texture(_) => "a texture",
        }
    }
}

pub type Env = HashMap<String, Value>;

static PRATT: LazyLock<PrattParser<Rule>> = LazyLock::new(|| {
    PrattParser::new()
        .op(Op::infix(Rule::add, Assoc::Left) | Op::infix(Rule::subtract, Assoc::Left))
        .op(Op::infix(Rule::multiply, Assoc::Left) | Op::infix(Rule::divide, Assoc::Left))
        .op(Op::prefix(Rule::negate) | Op::prefix(Rule::plus))
        .op(Op::postfix(Rule::component))
});

/// Evaluates an `expr` pair. `error(pair, message)` locates messages.
pub fn eval(
    pair: Pair<'_, Rule>,
    env: &Env,
    error: &dyn Fn(&Pair<'_, Rule>, String) -> SceneError,
) -> Result<Value, SceneError> {
    let whole = pair.clone();
    let value = PRATT
        .map_primary(|p| primary(p, env, error))
        .map_prefix(|op, v| {
            let v = v?;
            match op.as_rule() {
                Rule::negate => arithmetic(&op, Value::Float(-1.0), v, |a, b| a * b, error),
                _ => Ok(v),
            }
        })
        .map_postfix(|v, op| match (v?, op.as_str()) {
            (Value::Vector(v), ".x") => Ok(Value::Float(v.x)),
            (Value::Vector(v), ".y") => Ok(Value::Float(v.y)),
            (Value::Vector(v), ".z") => Ok(Value::Float(v.z)),
            (other, c) => Err(error(&op, format!("`{c}` needs a vector, not {}", other.kind()))),
        })
        .map_infix(|a, op, b| {
            let (a, b) = (a?, b?);
            match op.as_rule() {
                Rule::add => arithmetic(&op, a, b, |x, y| x + y, error),
                Rule::subtract => arithmetic(&op, a, b, |x, y| x - y, error),
                Rule::multiply => arithmetic(&op, a, b, |x, y| x * y, error),
                _ => {
                    let divisor_zero = match &b {
                        Value::Float(f) => *f == 0.0,
                        Value::Vector(v) => v.cmpeq(DVec3::ZERO).any(),
                        _ => false,
                    };
                    if divisor_zero {
                        return Err(error(&op, "division by zero".to_string()));
                    }
                    arithmetic(&op, a, b, |x, y| x / y, error)
                }
            }
        })
        .parse(pair.into_inner())?;
    let finite = match &value {
        Value::Float(f) => f.is_finite(),
        Value::Vector(v) => v.is_finite(),
        Value::Numbers(n) => n.iter().all(|f| f.is_finite()),
        _ => true,
    };
    if !finite {
        return Err(error(&whole, "this expression's value is not a finite number".to_string()));
    }
    Ok(value)
}

/// `+ - * /` on numbers and vectors: a number meets a vector component-wise (promotion).
fn arithmetic(
    op: &Pair<'_, Rule>,
    a: Value,
    b: Value,
    f: impl Fn(f64, f64) -> f64,
    error: &dyn Fn(&Pair<'_, Rule>, String) -> SceneError,
) -> Result<Value, SceneError> {
    let vector = |v: &Value| match v {
        Value::Float(x) => Some(DVec3::splat(*x)),
        Value::Vector(v) => Some(*v),
        _ => None,
    };
    match (&a, &b) {
        (Value::Float(x), Value::Float(y)) => Ok(Value::Float(f(*x, *y))),
        _ => match (vector(&a), vector(&b)) {
            (Some(x), Some(y)) => {
                Ok(Value::Vector(DVec3::new(f(x.x, y.x), f(x.y, y.y), f(x.z, y.z))))
            }
            _ => Err(error(
                op,
                format!("`{}` cannot combine {} and {}", op.as_str(), a.kind(), b.kind()),
            )),
        },
    }
}

fn primary(
    pair: Pair<'_, Rule>,
    env: &Env,
    error: &dyn Fn(&Pair<'_, Rule>, String) -> SceneError,
) -> Result<Value, SceneError> {
    match pair.as_rule() {
        Rule::number => pair
            .as_str()
            .parse()
            .map(Value::Float)
            .map_err(|_| error(&pair, format!("`{}` is not a number", pair.as_str()))),
        Rule::kw_pi => Ok(Value::Float(std::f64::consts::PI)),
        Rule::expr => eval(pair, env, error),
        Rule::ident => env.get(pair.as_str()).cloned().ok_or_else(|| {
            let mut message = format!("unknown identifier `{}`", pair.as_str());
            if let Some(guess) =
                super::parser::closest(pair.as_str(), env.keys().map(String::as_str))
            {
                message.push_str(&format!("; did you mean `{guess}`?"));
            }
            error(&pair, message)
        }),
        Rule::vector => {
            let mut numbers = Vec::new();
            for component in pair.clone().into_inner() {
                let span = component.clone();
                match eval(component, env, error)? {
                    Value::Float(f) => numbers.push(f),
                    other => {
                        return Err(error(
                            &span,
                            format!("a vector's components are numbers, not {}", other.kind()),
                        ));
                    }
                }
            }
            Ok(match numbers.as_slice() {
                [x, y, z] => Value::Vector(DVec3::new(*x, *y, *z)),
                _ => Value::Numbers(numbers),
            })
        }
        Rule::call => call(pair, env, error),
        _ => Err(error(&pair, "expected a number or vector".to_string())),
    }
}

fn call(
    pair: Pair<'_, Rule>,
    env: &Env,
    error: &dyn Fn(&Pair<'_, Rule>, String) -> SceneError,
) -> Result<Value, SceneError> {
    let mut inner = pair.clone().into_inner();
    let name = inner.next().map(|p| p.as_str()).unwrap_or_default();
    let mut args = Vec::new();
    for arg in inner {
        let span = arg.clone();
        match eval(arg, env, error)? {
            Value::Float(f) => args.push(f),
            other => {
                return Err(error(&span, format!("`{name}` takes numbers, not {}", other.kind())));
            }
        }
    }
    let arity = if matches!(name, "pow" | "min" | "max") { 2 } else { 1 };
    if args.len() != arity {
        return Err(error(
            &pair,
            format!("`{name}` takes {arity} argument(s), not {}", args.len()),
        ));
    }
    let (x, y) = (args[0], args.get(1).copied().unwrap_or(0.0));
    let domain = |ok: bool, what: &str| {
        if ok { Ok(()) } else { Err(error(&pair, format!("`{name}` of {x}: {what}"))) }
    };
    Ok(Value::Float(match name {
        "sin" => x.sin(),
        "cos" => x.cos(),
        "tan" => x.tan(),
        "asin" => domain((-1.0..=1.0).contains(&x), "outside [-1, 1]").map(|_| x.asin())?,
        "acos" => domain((-1.0..=1.0).contains(&x), "outside [-1, 1]").map(|_| x.acos())?,
        "atan" => x.atan(),
        "sqrt" => domain(x >= 0.0, "negative").map(|_| x.sqrt())?,
        "pow" => x.powf(y),
        "abs" => x.abs(),
        "min" => x.min(y),
        "max" => x.max(y),
        "radians" => x.to_radians(),
        _ => x.to_degrees(),
    }))
}
