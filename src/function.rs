//! POV-Ray's float functions (`function { }`), compiled once into a flat program for a small
//! stack machine and run per call without looking at the syntax again. `lang` compiles the
//! text into a `FloatFunction`; isosurfaces and the scene language's calls run it.

use std::sync::Arc;

use glam::{Affine3A, DVec3, Vec3};

use crate::geometry::ScalarField;
use crate::graph::{FieldShape, TextureNode};
use crate::texture::{ImageMap, ImageMapError, Texture, noise, shaped_value};

/// The deepest stack a program may need: far beyond what written expressions reach (a sum is
/// evaluated left to right and needs two places however long it is).
pub const MAX_STACK: usize = 64;

/// A compiled function of `parameters` numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct FloatFunction {
    parameters: usize,
    program: Vec<Op>,
}

/// One step of a program: it pops its operands and pushes its result.
#[derive(Debug, Clone, PartialEq)]
pub enum Op {
    Number(f64),
    Parameter(usize),
    Unary(Unary),
    Binary(Binary),
    /// `select(a, b, c)`: b where a < 0, else c.
    Select3,
    /// `select(a, b, c, d)`: b where a < 0, c where a = 0, d where a > 0.
    Select4,
    /// `condition ? then : otherwise` (both sides are evaluated: functions have no effects).
    Choose,
    /// Another function, its arguments on the stack.
    Call(Arc<FloatFunction>),
    /// `pattern { ... }` at the point (x, y, z) on the stack.
    Pattern(Box<PatternField>),
    /// POV-Ray's `f_noise3d` (`internal(76)`): its noise in [0, 1] at (x, y, z).
    Noise,
    /// A component of a colour function's colour at (x, y, z) on the stack.
    Pigment(Box<PigmentChannel>),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Unary {
    Negate,
    Not,
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Sinh,
    Cosh,
    Tanh,
    Asinh,
    Acosh,
    Atanh,
    Sqrt,
    Sqr,
    Abs,
    Exp,
    /// Natural logarithm.
    Ln,
    /// Base-10 logarithm, as POV-Ray's `log`.
    Log,
    Floor,
    Ceil,
    /// Truncation towards zero.
    Int,
    Radians,
    Degrees,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Binary {
    Add,
    Subtract,
    Multiply,
    Divide,
    Pow,
    Min,
    Max,
    /// The sign of the dividend, as C's `fmod` and POV-Ray's `mod`.
    Mod,
    Atan2,
    Less,
    LessEqual,
    Greater,
    GreaterEqual,
    Equal,
    NotEqual,
    And,
    Or,
}

/// A pattern's value as a function: its shape, and the map from the function's points to the
/// pattern's space (the inverse of its transforms).
#[derive(Debug, Clone, PartialEq)]
pub struct PatternField {
    pub shape: FieldShape,
    pub to_pattern: Affine3A,
}

/// The component `.gray` of a colour, after x, y, z, filter and transmit (0 to 4).
pub const GRAY: usize = 5;

/// Component `channel` (0 to 4, or `GRAY`) of POV-Ray's colour <red, green, blue, filter,
/// transmit>.
pub fn component(colour: &[f64; 5], channel: usize) -> f64 {
    match channel {
        // POV-Ray's weights (its `Greyscale`).
        GRAY => 0.297 * colour[0] + 0.589 * colour[1] + 0.114 * colour[2],
        _ => colour[channel],
    }
}

/// POV-Ray's colour function (`function { pigment { } }`): its pigment, compiled once.
#[derive(Debug, Clone)]
pub struct ColourFunction {
    /// The pigment as the scene gives it: its colour, filter and filter + transmit (which
    /// equality compares: a compiled texture has none).
    pub pigment: [TextureNode; 3],
    textures: [Texture; 3],
}

impl PartialEq for ColourFunction {
    fn eq(&self, other: &Self) -> bool {
        self.pigment == other.pigment
    }
}

impl ColourFunction {
    /// Compiles the pigment of colour `colour`, `filter` and `through` (filter + transmit,
    /// grey); `load` reads its images.
    pub fn new(
        colour: TextureNode,
        filter: TextureNode,
        through: TextureNode,
        load: &mut dyn FnMut(&std::path::Path) -> Result<Arc<ImageMap>, ImageMapError>,
    ) -> Result<ColourFunction, ImageMapError> {
        let textures = [
            Texture::new(&colour, load)?,
            Texture::new(&filter, load)?,
            Texture::new(&through, load)?,
        ];
        Ok(ColourFunction { pigment: [colour, filter, through], textures })
    }

    /// POV-Ray's colour <red, green, blue, filter, transmit> at `p`.
    pub fn colour(&self, p: Vec3) -> [f64; 5] {
        let [colour, filter, through] = &self.textures;
        let rgb = colour.eval(p).as_dvec3();
        let filter = f64::from(filter.eval(p).x);
        let through = f64::from(through.eval(p).x);
        [rgb.x, rgb.y, rgb.z, filter, through - filter]
    }
}

/// A component of a colour function's colour (`F(x, y, z).red`), in a function.
#[derive(Debug, Clone, PartialEq)]
pub struct PigmentChannel {
    pub function: Arc<ColourFunction>,
    /// 0 to 4, or `GRAY`.
    pub channel: usize,
}

impl Op {
    /// How the op changes the stack's depth.
    fn stack_change(&self) -> isize {
        match self {
            Op::Number(_) | Op::Parameter(_) => 1,
            Op::Unary(_) => 0,
            Op::Binary(_) => -1,
            Op::Select3 | Op::Choose | Op::Pattern(_) | Op::Noise | Op::Pigment(_) => -2,
            Op::Select4 => -3,
            Op::Call(f) => 1 - f.parameters as isize,
        }
    }
}

/// Builds a program op by op, keeping count of its stack's depth.
#[derive(Debug)]
pub struct Builder {
    parameters: usize,
    program: Vec<Op>,
    depth: usize,
}

impl Builder {
    pub fn new(parameters: usize) -> Builder {
        Builder { parameters, program: Vec::new(), depth: 0 }
    }

    /// Appends `op`; an error (the depth) where the program would need more than `MAX_STACK`.
    pub fn push(&mut self, op: Op) -> Result<(), usize> {
        let depth = self.depth as isize + op.stack_change();
        debug_assert!(depth >= 1, "an op finds its operands on the stack");
        if let Op::Parameter(i) = op {
            debug_assert!(i < self.parameters);
        }
        if depth as usize > MAX_STACK {
            return Err(depth as usize);
        }
        self.depth = depth as usize;
        self.program.push(op);
        Ok(())
    }

    /// The function, once the program leaves one value.
    pub fn finish(self) -> FloatFunction {
        debug_assert_eq!(self.depth, 1, "a function's program leaves its value");
        FloatFunction { parameters: self.parameters, program: self.program }
    }
}

/// An isosurface's function of (x, y, z).
impl ScalarField for FloatFunction {
    fn value(&self, p: DVec3) -> f64 {
        self.eval(&[p.x, p.y, p.z])
    }
}

impl FloatFunction {
    pub fn parameters(&self) -> usize {
        self.parameters
    }

    /// The value at `arguments` (as many as the parameters).
    pub fn eval(&self, arguments: &[f64]) -> f64 {
        debug_assert_eq!(arguments.len(), self.parameters);
        let mut stack = [0.0f64; MAX_STACK];
        let mut top = 0;
        for op in &self.program {
            match op {
                Op::Number(v) => {
                    stack[top] = *v;
                    top += 1;
                }
                Op::Parameter(i) => {
                    stack[top] = arguments[*i];
                    top += 1;
                }
                Op::Unary(f) => stack[top - 1] = unary(*f, stack[top - 1]),
                Op::Binary(f) => {
                    top -= 1;
                    stack[top - 1] = binary(*f, stack[top - 1], stack[top]);
                }
                Op::Select3 => {
                    top -= 2;
                    let [a, b, c] = [stack[top - 1], stack[top], stack[top + 1]];
                    stack[top - 1] = if a < 0.0 { b } else { c };
                }
                Op::Select4 => {
                    top -= 3;
                    let [a, b, c, d] = [stack[top - 1], stack[top], stack[top + 1], stack[top + 2]];
                    stack[top - 1] = if a < 0.0 {
                        b
                    } else if a == 0.0 {
                        c
                    } else {
                        d
                    };
                }
                Op::Choose => {
                    top -= 2;
                    let [condition, then, otherwise] = [stack[top - 1], stack[top], stack[top + 1]];
                    stack[top - 1] = if condition != 0.0 { then } else { otherwise };
                }
                Op::Call(f) => {
                    let first = top - f.parameters;
                    stack[first] = f.eval(&stack[first..top]);
                    top = first + 1;
                }
                Op::Pattern(pattern) => {
                    top -= 2;
                    let p = point(&stack[top - 1..top + 2]);
                    let q = pattern.to_pattern.transform_point3(p);
                    stack[top - 1] = f64::from(shaped_value(&pattern.shape, q));
                }
                Op::Noise => {
                    top -= 2;
                    stack[top - 1] = f64::from(noise(point(&stack[top - 1..top + 2])));
                }
                Op::Pigment(pigment) => {
                    top -= 2;
                    let colour = pigment.function.colour(point(&stack[top - 1..top + 2]));
                    stack[top - 1] = component(&colour, pigment.channel);
                }
            }
        }
        stack[0]
    }
}

fn point(xyz: &[f64]) -> Vec3 {
    Vec3::new(xyz[0] as f32, xyz[1] as f32, xyz[2] as f32)
}

fn truth(b: bool) -> f64 {
    if b { 1.0 } else { 0.0 }
}

pub fn unary(f: Unary, x: f64) -> f64 {
    match f {
        Unary::Negate => -x,
        Unary::Not => truth(x == 0.0),
        Unary::Sin => x.sin(),
        Unary::Cos => x.cos(),
        Unary::Tan => x.tan(),
        Unary::Asin => x.asin(),
        Unary::Acos => x.acos(),
        Unary::Atan => x.atan(),
        Unary::Sinh => x.sinh(),
        Unary::Cosh => x.cosh(),
        Unary::Tanh => x.tanh(),
        Unary::Asinh => x.asinh(),
        Unary::Acosh => x.acosh(),
        Unary::Atanh => x.atanh(),
        Unary::Sqrt => x.sqrt(),
        Unary::Sqr => x * x,
        Unary::Abs => x.abs(),
        Unary::Exp => x.exp(),
        Unary::Ln => x.ln(),
        Unary::Log => x.log10(),
        Unary::Floor => x.floor(),
        Unary::Ceil => x.ceil(),
        Unary::Int => x.trunc(),
        Unary::Radians => x.to_radians(),
        Unary::Degrees => x.to_degrees(),
    }
}

pub fn binary(f: Binary, a: f64, b: f64) -> f64 {
    match f {
        Binary::Add => a + b,
        Binary::Subtract => a - b,
        Binary::Multiply => a * b,
        Binary::Divide => a / b,
        Binary::Pow => a.powf(b),
        Binary::Min => a.min(b),
        Binary::Max => a.max(b),
        Binary::Mod => a % b,
        Binary::Atan2 => a.atan2(b),
        Binary::Less => truth(a < b),
        Binary::LessEqual => truth(a <= b),
        Binary::Greater => truth(a > b),
        Binary::GreaterEqual => truth(a >= b),
        Binary::Equal => truth(a == b),
        Binary::NotEqual => truth(a != b),
        Binary::And => truth(a != 0.0 && b != 0.0),
        Binary::Or => truth(a != 0.0 || b != 0.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn build(parameters: usize, ops: Vec<Op>) -> FloatFunction {
        let mut builder = Builder::new(parameters);
        for op in ops {
            builder.push(op).unwrap();
        }
        builder.finish()
    }

    #[test]
    fn a_program_computes_its_expression() {
        // sqrt(x*x + y*y + z*z) - r, the sphere of radius r.
        let sphere = build(
            4,
            vec![
                Op::Parameter(0),
                Op::Unary(Unary::Sqr),
                Op::Parameter(1),
                Op::Unary(Unary::Sqr),
                Op::Binary(Binary::Add),
                Op::Parameter(2),
                Op::Unary(Unary::Sqr),
                Op::Binary(Binary::Add),
                Op::Unary(Unary::Sqrt),
                Op::Parameter(3),
                Op::Binary(Binary::Subtract),
            ],
        );
        assert_eq!(sphere.eval(&[3.0, 4.0, 0.0, 1.0]), 4.0);
        // A call: 2 * sphere(a, 0, 0, 1).
        let twice = build(
            1,
            vec![
                Op::Number(2.0),
                Op::Parameter(0),
                Op::Number(0.0),
                Op::Number(0.0),
                Op::Number(1.0),
                Op::Call(Arc::new(sphere)),
                Op::Binary(Binary::Multiply),
            ],
        );
        assert_eq!(twice.eval(&[-5.0]), 8.0);
    }

    #[test]
    fn select_and_choose_pick_by_sign_and_truth() {
        let select = |a: f64| {
            build(0, vec![Op::Number(a), Op::Number(1.0), Op::Number(2.0), Op::Select3]).eval(&[])
        };
        assert_eq!((select(-0.5), select(0.0), select(3.0)), (1.0, 2.0, 2.0));
        let select4 = |a: f64| {
            let ops =
                vec![Op::Number(a), Op::Number(1.0), Op::Number(2.0), Op::Number(3.0), Op::Select4];
            build(0, ops).eval(&[])
        };
        assert_eq!((select4(-0.5), select4(0.0), select4(3.0)), (1.0, 2.0, 3.0));
        let choose = |c: f64| {
            build(0, vec![Op::Number(c), Op::Number(1.0), Op::Number(2.0), Op::Choose]).eval(&[])
        };
        assert_eq!((choose(1.0), choose(0.0)), (1.0, 2.0));
    }

    #[test]
    fn built_ins_follow_their_definitions() {
        let x: f64 = 0.37;
        let cases = [
            (Unary::Sinh, (x.exp() - (-x).exp()) / 2.0),
            (Unary::Cosh, (x.exp() + (-x).exp()) / 2.0),
            (Unary::Asinh, (x + (x * x + 1.0).sqrt()).ln()),
            (Unary::Atanh, 0.5 * ((1.0 + x) / (1.0 - x)).ln()),
            (Unary::Log, x.ln() / 10f64.ln()),
            (Unary::Sqr, x * x),
            (Unary::Degrees, x * 180.0 / std::f64::consts::PI),
            (Unary::Not, 0.0),
        ];
        for (f, expected) in cases {
            assert!((unary(f, x) - expected).abs() < 1e-12, "{f:?}");
        }
        assert_eq!(unary(Unary::Acosh, 1.0), 0.0);
        assert_eq!(unary(Unary::Int, -2.7), -2.0);
        assert_eq!(binary(Binary::Mod, -7.0, 3.0), -1.0, "the sign of the dividend");
        assert_eq!(binary(Binary::Atan2, 1.0, 0.0), std::f64::consts::FRAC_PI_2);
        assert_eq!(binary(Binary::Pow, 2.0, 10.0), 1024.0);
        assert_eq!(binary(Binary::LessEqual, 1.0, 1.0), 1.0);
        assert_eq!(binary(Binary::And, 1.0, 0.0), 0.0);
        assert_eq!(binary(Binary::Or, 1.0, 0.0), 1.0);
    }

    #[test]
    fn the_stack_bound_is_kept() {
        let mut builder = Builder::new(0);
        for _ in 0..MAX_STACK {
            builder.push(Op::Number(1.0)).unwrap();
        }
        assert_eq!(builder.push(Op::Number(1.0)), Err(MAX_STACK + 1));
    }
}
