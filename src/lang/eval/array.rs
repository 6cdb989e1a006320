//! Arrays: literals of one or more dimensions, and the position of an element.

use std::sync::Arc;

use super::{Evaluator, MAX_ARRAY_ELEMENTS_MADE};
use crate::diagnostic::{SceneError, Span};
use crate::lang::syntax::{ArrayElement, ArrayLiteral, Expr, Ident};
use crate::lang::value::{ARRAY_CHUNK, Array, MAX_ARRAY_ELEMENTS, Value};

impl Evaluator {
    pub(super) fn array(&mut self, literal: &ArrayLiteral) -> Result<Value, SceneError> {
        let mut dimensions = Vec::new();
        for d in &literal.dimensions {
            let size = self.integer(d, 1, MAX_ARRAY_ELEMENTS as u64)? as usize;
            dimensions.push(size);
        }
        let total: usize =
            dimensions.iter().try_fold(1usize, |a, &d| a.checked_mul(d)).unwrap_or(usize::MAX);
        if total > MAX_ARRAY_ELEMENTS {
            return Err(SceneError::at(
                &literal.span,
                format!("an array of more than {} elements", MAX_ARRAY_ELEMENTS),
            ));
        }
        let array = match &literal.elements {
            None => Array::unset(dimensions),
            Some(rows) => {
                let mut elements = Vec::with_capacity(total);
                self.array_rows(rows, &dimensions, &literal.span, &mut elements)?;
                Array::of(dimensions, &elements)
            }
        };
        self.count_array_elements(array.chunk_count() + total.min(ARRAY_CHUNK), &literal.span)?;
        Ok(Value::Array(Arc::new(array)))
    }

    /// `A[i]...[k] = value`: copies only what another array shares (the list of chunks, the
    /// element's chunk), counted in the scene's budget of array elements.
    pub(super) fn set_element(
        &mut self,
        name: &Ident,
        local: bool,
        at: &[(f64, Span)],
        value: Value,
    ) -> Result<(), SceneError> {
        let Some(slot) = self.slot_mut(&name.name, local) else {
            return Err(self.unknown(name));
        };
        let Value::Array(array) = slot else {
            return Err(SceneError::at(
                &name.span,
                format!("`{}` is {}, not an array", name.name, slot.kind()),
            ));
        };
        let flat = element_index(array, Some(&name.name), at)?;
        let list = if Arc::get_mut(array).is_some() { 0 } else { array.chunk_count() };
        let copied = list + Arc::make_mut(array).set(flat, value);
        self.count_array_elements(copied, &name.span)
    }

    /// Whether `name` is declared (`#ifdef (Name)`); with `indices`, whether that element of
    /// the array `name` is set (`#ifdef (A[i])`, `defined(A[i])`), as POV-Ray tells.
    pub(super) fn is_set(&mut self, name: &Ident, indices: &[Expr]) -> Result<bool, SceneError> {
        if indices.is_empty() {
            return Ok(self.is_defined(&name.name));
        }
        let array = match self.lookup(&name.name) {
            None => return Ok(false),
            Some(Value::Array(array)) => array.clone(),
            Some(other) => {
                return Err(SceneError::at(
                    &name.span,
                    format!("`{}` is {}, not an array", name.name, other.kind()),
                ));
            }
        };
        let mut at = Vec::new();
        for index in indices {
            at.push((self.number(index, "an index")?, index.span.clone()));
        }
        let flat = element_index(&array, Some(&name.name), &at)?;
        Ok(array.get(flat).is_some())
    }

    /// Counts `made` more elements (or chunk pointers) made or copied in this scene.
    fn count_array_elements(&mut self, made: usize, at: &Span) -> Result<(), SceneError> {
        self.array_elements += made as u64;
        if self.array_elements > MAX_ARRAY_ELEMENTS_MADE {
            return Err(SceneError::at(
                at,
                format!(
                    "more than {MAX_ARRAY_ELEMENTS_MADE} array elements made or copied in this \
                     scene"
                ),
            ));
        }
        Ok(())
    }

    fn array_rows(
        &mut self,
        row: &[ArrayElement],
        dimensions: &[usize],
        span: &Span,
        out: &mut Vec<Option<Value>>,
    ) -> Result<(), SceneError> {
        if row.len() != dimensions[0] {
            return Err(SceneError::at(
                span,
                format!(
                    "the array's size is {} here, but {} elements are given",
                    dimensions[0],
                    row.len()
                ),
            ));
        }
        for element in row {
            match (element, dimensions.len()) {
                (ArrayElement::Row(inner, at), n) if n > 1 => {
                    self.array_rows(inner, &dimensions[1..], at, out)?
                }
                (ArrayElement::Value(value, _), 1) => out.push(Some(self.declared(value, None)?)),
                (ArrayElement::Row(_, at), _) => {
                    return Err(SceneError::at(at, "a row `{ ... }` where an element is expected"));
                }
                (ArrayElement::Value(_, at), _) => {
                    return Err(SceneError::at(
                        at,
                        "an element where a row `{ ... }` of the next dimension is expected",
                    ));
                }
            }
        }
        Ok(())
    }
}

/// The flat position of an element, or a located error naming the array (`name`, if it has one)
/// and its size.
pub(super) fn element_index(
    array: &Array,
    name: Option<&str>,
    at: &[(f64, Span)],
) -> Result<usize, SceneError> {
    let array_name = name.map_or("the array".to_string(), |n| format!("`{n}`"));
    if at.len() != array.dimensions.len() {
        let span = &at.last().expect("an index").1;
        return Err(SceneError::at(
            span,
            format!("{array_name} has {} dimensions, not {}", array.dimensions.len(), at.len()),
        ));
    }
    let mut flat = 0;
    for ((index, span), &size) in at.iter().zip(&array.dimensions) {
        if index.fract() != 0.0 || *index < 0.0 || *index >= size as f64 {
            return Err(SceneError::at(
                span,
                format!(
                    "index {index} is out of bounds: {array_name} has size {size} (indices 0 to {})",
                    size - 1
                ),
            ));
        }
        flat = flat * size + *index as usize;
    }
    Ok(flat)
}
