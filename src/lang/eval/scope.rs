//! Scopes: the global one, one per included file, one per macro call; names looked up from the
//! innermost, `#local` and `#declare` bound as POV-Ray does, parameters passed by reference.

use std::collections::HashMap;

use super::Evaluator;
use crate::diagnostic::SceneError;
use crate::lang::syntax::Ident;
use crate::lang::value::Value;
use crate::lang::{library, parser, povray};

#[derive(Default)]
pub(super) struct Scope {
    pub(super) names: HashMap<String, Slot>,
}

impl Scope {
    /// The slot `name` names here. A lookup walks every scope from the innermost, and a macro
    /// calling itself nests a scope of a parameter or two per call: those few names are
    /// compared directly, not hashed once per scope with the scope's own keys (which took half
    /// the time of a million macro calls, nested 40 deep).
    fn get(&self, name: &str) -> Option<&Slot> {
        const FEW: usize = 8;
        match self.names.len() <= FEW {
            true => self.names.iter().find(|(key, _)| key.as_str() == name).map(|(_, slot)| slot),
            false => self.names.get(name),
        }
    }
}

pub(super) enum Slot {
    Value(Value),
    /// A macro's parameter passed by reference: the caller's variable, in scope `scope`.
    Alias {
        scope: usize,
        name: String,
    },
}

impl Evaluator {
    /// The scope and name where `name` lives, following a by-reference parameter; the global
    /// scope if it is not bound (a `#declare` there then creates it, as in POV-Ray).
    pub(super) fn resolve(&self, name: &str) -> (usize, String) {
        for (index, scope) in self.scopes.iter().enumerate().rev() {
            match scope.get(name) {
                Some(Slot::Value(_)) => return (index, name.to_string()),
                Some(Slot::Alias { scope, name }) => return (*scope, name.clone()),
                None => {}
            }
        }
        (0, name.to_string())
    }

    pub(super) fn lookup(&self, name: &str) -> Option<&Value> {
        for scope in self.scopes.iter().rev() {
            match scope.get(name) {
                Some(Slot::Value(v)) => return Some(v),
                Some(Slot::Alias { scope, name }) => {
                    return match self.scopes[*scope].get(name) {
                        Some(Slot::Value(v)) => Some(v),
                        Some(Slot::Alias { .. }) | None => None,
                    };
                }
                None => {}
            }
        }
        None
    }

    pub(super) fn is_defined(&self, name: &str) -> bool {
        self.lookup(name).is_some()
    }

    /// `#local` binds in the innermost scope; `#declare` changes the variable the name stands
    /// for where it lives (through a by-reference parameter too), or makes a global one.
    pub(super) fn bind(&mut self, name: &str, value: Value, local: bool) {
        if let Some(slot) = self.slot_mut(name, local) {
            *slot = value;
            return;
        }
        let (scope, name) = match local {
            true => (self.scopes.len() - 1, name.to_string()),
            false => self.resolve(name),
        };
        self.scopes[scope].names.insert(name, Slot::Value(value));
    }

    /// The value a name stands for, to change it in place (`None` if it has none yet).
    pub(super) fn slot_mut(&mut self, name: &str, local: bool) -> Option<&mut Value> {
        let found = match local {
            true => {
                Some(self.scopes.len() - 1).filter(|&i| self.scopes[i].names.contains_key(name))
            }
            false => self.scopes.iter().rposition(|s| s.names.contains_key(name)),
        };
        let index = found?;
        let (target, target_name) = match &self.scopes[index].names[name] {
            Slot::Value(_) => (index, None),
            Slot::Alias { scope, name } => (*scope, Some(name.clone())),
        };
        let key = target_name.as_deref().unwrap_or(name);
        match self.scopes[target].names.get_mut(key) {
            Some(Slot::Value(v)) => Some(v),
            Some(Slot::Alias { .. }) | None => None,
        }
    }

    pub(super) fn undef(&mut self, name: &str) {
        for scope in self.scopes.iter_mut().rev() {
            if scope.names.remove(name).is_some() {
                return;
            }
        }
    }

    pub(super) fn unknown(&self, ident: &Ident) -> SceneError {
        self.unknown_as(ident, "identifier")
    }

    /// An unknown name, where a `what` (identifier, macro) was expected.
    pub(super) fn unknown_as(&self, ident: &Ident, what: &str) -> SceneError {
        if let Some(message) = povray::message(&ident.name, None) {
            return SceneError::at(&ident.span, message);
        }
        if let Some(why) = library::left_out(&ident.name) {
            return SceneError::at(&ident.span, format!("`{}`: {why}", ident.name));
        }
        let mut message = format!("unknown {what} `{}`", ident.name);
        let names = self.scopes.iter().flat_map(|s| s.names.keys().map(String::as_str));
        if let Some(guess) = parser::closest(&ident.name, names) {
            message.push_str(&format!("; did you mean `{guess}`?"));
        }
        SceneError::at(&ident.span, message)
    }
}
