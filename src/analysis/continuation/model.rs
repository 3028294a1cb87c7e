//! What continuation needs of a model at one parameter point, whatever the model: its
//! periodic responses shot with their monodromy ([`Shootable`]), brute-force responses to
//! seed branches ([`Oscillator`]), and a parameter to move along, named as the user writes
//! it. Branches, bifurcation curves, the hunter and maps are generic over it; the built-in
//! DEA ([`Params`]) and a written model ([`EquationSystem`]) implement it.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::analysis::Oscillator;
use crate::analysis::orbit::shooting::Shootable;
use crate::model::equations::EquationSystem;
use crate::model::{ParamSpec, Params};

/// A model whose periodic responses can be continued.
pub trait Continuable: Shootable + Oscillator<Parameter: PartialEq> {
    /// The model's values, for the record of a result.
    fn base(&self) -> ModelBase;
}

/// The model a branch or curve was continued about: the built-in model's parameters, or a
/// written model's values by name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ModelBase {
    BuiltIn(ParamSpec),
    Written(BTreeMap<String, f64>),
}

impl Continuable for Params {
    fn base(&self) -> ModelBase {
        ModelBase::BuiltIn(self.to_spec())
    }
}

impl Continuable for EquationSystem {
    fn base(&self) -> ModelBase {
        ModelBase::Written(
            self.model()
                .parameters()
                .iter()
                .zip(self.values())
                .map(|(p, &v)| (p.name.clone(), v))
                .collect(),
        )
    }
}
