//! POV-Ray's `height_field`: its heights read from an image file (found as a font is: beside the
//! scene, in the include folders, in POV-Ray's library) or sampled from a function on a grid,
//! made into a mesh of the sheet, which is seen; the heights are kept for the solid below it,
//! which CSG reads (`mesh::height_field`).

use std::sync::Arc;

use glam::Vec3;

use super::Evaluator;
use crate::diagnostic::{SceneError, Span};
use crate::function::{GRAY, component};
use crate::graph::ShapeNode;
use crate::lang::syntax::{Expr, FunctionBody, FunctionDef, HeightField, HeightSource, Ident};
use crate::mesh::height_field::tessellate;
use crate::mesh::heights::{self, HeightFormat, Heights, check_size};

impl Evaluator {
    pub(super) fn height_field(
        &mut self,
        field: &HeightField,
        span: &Span,
    ) -> Result<ShapeNode, SceneError> {
        let heights = match &field.source {
            HeightSource::Image { format, file, options } => {
                self.image_heights(format.as_ref(), file, options)?
            }
            HeightSource::Function { width, height, body } => {
                self.function_heights(width, height, body)?
            }
        };
        let water_level = match &field.water_level {
            None => 0.0,
            Some(level) => {
                let value = self.number(level, "`water_level`")?;
                if !(0.0..=1.0).contains(&value) {
                    return Err(SceneError::at(
                        &level.span,
                        format!("a height field's water_level is from 0 to 1, not {value}"),
                    ));
                }
                value as f32
            }
        };
        // The last `smooth` written counts; `hierarchy` only shapes POV-Ray's own bounding.
        let smooth = field.flags.iter().rev().find(|(word, _)| word.name == "smooth");
        let smooth = smooth.is_some_and(|(_, on)| *on);
        let mesh = tessellate(&heights, water_level, smooth).ok_or_else(|| {
            SceneError::at(
                span,
                format!("the whole height field is below its water_level {water_level}"),
            )
        })?;
        Ok(ShapeNode::HeightField { sheet: Arc::new(mesh), heights: Arc::new(heights) })
    }

    /// The heights of `height_field { [type] "file" [gamma g] [premultiplied] }`.
    fn image_heights(
        &mut self,
        format: Option<&Ident>,
        file: &Expr,
        options: &[(Ident, Option<Expr>)],
    ) -> Result<Heights, SceneError> {
        let name = self.string(file, "the height field's image")?;
        for (word, value) in options {
            if let Some(value) = value {
                self.number(value, &format!("`{}`", word.name))?;
            }
            self.warnings.push(format!(
                "{:?}: warning: `{}` is read and not used: a height field's heights are its \
                 image's values as stored",
                self.here(&word.span),
                word.name
            ));
        }
        let format = match format {
            Some(word) => image_format(&word.name).ok_or_else(|| {
                SceneError::at(&word.span, unreadable_format(&format!("`{}`", word.name)))
            })?,
            None => {
                let extension = std::path::Path::new(&name)
                    .extension()
                    .map(|e| e.to_string_lossy().to_ascii_lowercase());
                let word = match extension.as_deref() {
                    Some("jpg") => Some("jpeg"),
                    other => other,
                };
                word.and_then(image_format).ok_or_else(|| {
                    SceneError::at(
                        &file.span,
                        unreadable_format(&format!(
                            "`{name}`, whose type is not written (a type word such as `png` \
                             before the name, or its extension, says it)"
                        )),
                    )
                })?
            }
        };
        let path = self.find_in_library(&file.span, &[name], "the height field's image")?;
        heights::read(&path, format).map_err(|e| SceneError::at(&file.span, e.to_string()))
    }

    /// The heights of `height_field { function W, H { body } }`: as POV-Ray makes its function
    /// image, the value at (x, y, 0) for x = column / (W − 1) and y = row / (H − 1) (a pigment's
    /// gray), clamped to [0, 1]; row 0 stands where an image's top row does.
    fn function_heights(
        &mut self,
        width: &Expr,
        height: &Expr,
        body: &FunctionDef,
    ) -> Result<Heights, SceneError> {
        let [columns, rows] =
            [width, height].map(|e| (e, self.number(e, "the height field's size")));
        let mut size = [0usize; 2];
        for (slot, (expr, value)) in size.iter_mut().zip([columns, rows]) {
            let value = value?;
            if value.fract() != 0.0 || !(0.0..=1e9).contains(&value) {
                return Err(SceneError::at(
                    &expr.span,
                    format!(
                        "a height field's function size is a whole number of samples, not {value}"
                    ),
                ));
            }
            *slot = value as usize;
        }
        let [columns, rows] = size;
        check_size(columns, rows).map_err(|e| SceneError::at(&width.span, e.to_string()))?;
        let sample: Box<dyn Fn(f64, f64) -> f64> = match &body.body {
            FunctionBody::Pigment(pigment) => {
                let function = self.colour_function(pigment)?;
                Box::new(move |x, y| {
                    component(&function.colour(Vec3::new(x as f32, y as f32, 0.0)), GRAY)
                })
            }
            FunctionBody::Expr(_) | FunctionBody::Pattern(_) => {
                let function = self.float_function(body)?;
                if function.parameters() != 3 {
                    return Err(SceneError::at(
                        &body.span,
                        "a height field's function takes x, y and z",
                    ));
                }
                Box::new(move |x, y| function.eval(&[x, y, 0.0]))
            }
            FunctionBody::Transform(_) => {
                return Err(SceneError::at(
                    &body.span,
                    "a height field's function gives a number: a `transform` function moves points",
                ));
            }
        };
        let mut values = Vec::with_capacity(columns * rows);
        for row in 0..rows {
            let y = row as f64 / (rows - 1) as f64;
            for column in 0..columns {
                let value = sample(column as f64 / (columns - 1) as f64, y);
                // Stored as POV-Ray stores it, in 16 bits (NaN as 0).
                let stored = (value.clamp(0.0, 1.0) * 65535.0).round();
                values.push(if stored.is_nan() { 0.0 } else { stored as f32 / 65535.0 });
            }
        }
        Ok(Heights { columns, rows, values })
    }
}

/// The format of a height field's image type word, where raydiance reads it.
fn image_format(word: &str) -> Option<HeightFormat> {
    match word {
        "png" => Some(HeightFormat::Png),
        "jpeg" => Some(HeightFormat::Jpeg),
        "pgm" | "ppm" => Some(HeightFormat::Netpbm),
        "tga" => Some(HeightFormat::Tga),
        _ => None,
    }
}

/// The message for an image raydiance does not read as a height field.
fn unreadable_format(what: &str) -> String {
    format!(
        "{what}: raydiance reads a height field from a `png`, `jpeg`, `pgm`, `ppm` or `tga` image \
         or a `function` (not from POV-Ray's gif, pot, tiff, iff, sys, exr or hdr images)"
    )
}
