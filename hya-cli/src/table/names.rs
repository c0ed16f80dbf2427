//! Column names and units: how a header cell reads (`name [unit]`) and the names hya gives the
//! columns of an arm's quantities (`q_J [rad]`, `tau_J [N m]`, … for each joint J).

use std::fmt;

use hya_core::model::{JointKind, TreeModel};

/// One column of a header: its name, and its unit if the header gives one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Column {
    /// The name, without the unit.
    pub name: String,
    /// The unit, as written between the brackets.
    pub unit: Option<String>,
}

impl Column {
    /// A column with a unit.
    pub fn new(name: impl Into<String>, unit: impl Into<String>) -> Self {
        Self { name: name.into(), unit: Some(unit.into()) }
    }

    /// A column whose unit is not known (a channel of `hya filter` read without one).
    pub fn bare(name: impl Into<String>) -> Self {
        Self { name: name.into(), unit: None }
    }

    /// A header cell: `name [unit]` (a blank before the bracket), or a name alone (`q[0]` is a
    /// name: an index, not a unit).
    pub fn from_header(cell: &str) -> Self {
        let cell = cell.trim();
        if let Some(open) = cell.strip_suffix(']').and_then(|c| c.rfind(" [")) {
            let (name, open) = (cell[..open].trim(), open + 1);
            if !name.is_empty() {
                return Self::new(name, cell[open + 1..cell.len() - 1].trim());
            }
        }
        Self::bare(cell)
    }

    /// Whether a header's `self` may be read as `wanted`: same name, and the same unit where both
    /// give one ([`same_unit`]).
    pub fn unit_fits(&self, wanted: &Column) -> bool {
        match (&self.unit, &wanted.unit) {
            (Some(ours), Some(theirs)) => same_unit(ours, theirs),
            _ => true,
        }
    }
}

impl fmt::Display for Column {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.unit {
            Some(unit) => write!(f, "{} [{unit}]", self.name),
            None => f.write_str(&self.name),
        }
    }
}

/// Whether two unit texts name the same unit: equal once blanks and the product signs `·`, `*`
/// and `.` are dropped and `²` is read as `^2` (`N m`, `N·m` and `Nm` are one unit).
pub fn same_unit(a: &str, b: &str) -> bool {
    let key = |u: &str| -> String {
        u.chars().filter(|c| !c.is_whitespace() && !matches!(c, '·' | '*' | '.')).collect::<String>().replace('²', "^2")
    };
    key(a) == key(b)
}

/// A quantity with one column per joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Unit {
    /// Joint position `q`: rad or m.
    Position,
    /// Joint velocity `q̇`: rad/s or m/s.
    Velocity,
    /// Joint acceleration `q̈`: rad/s² or m/s².
    Acceleration,
    /// Joint torque or force `τ`: N m or N.
    Effort,
}

impl Unit {
    /// The unit of this quantity for a joint of `kind`.
    pub fn of(self, kind: JointKind) -> &'static str {
        let revolute = kind == JointKind::Revolute;
        match self {
            Self::Position => kind.position_unit(),
            Self::Velocity if revolute => "rad/s",
            Self::Velocity => "m/s",
            Self::Acceleration if revolute => "rad/s^2",
            Self::Acceleration => "m/s^2",
            Self::Effort => kind.effort_unit(),
        }
    }
}

/// The joints of a model as the columns of its logs are named: `prefix_J` for each joint J.
#[derive(Debug, Clone)]
pub struct Joints {
    joints: Vec<(String, JointKind)>,
}

impl Joints {
    /// The joints of `model`, in its order.
    pub fn of(model: &TreeModel) -> Self {
        Self { joints: model.bodies().iter().map(|b| (b.joint.clone(), b.kind)).collect() }
    }

    /// How many joints.
    pub fn len(&self) -> usize {
        self.joints.len()
    }

    /// One column per joint: `prefix_J [unit]`.
    pub fn columns(&self, prefix: &str, unit: Unit) -> Vec<Column> {
        self.joints.iter().map(|(joint, kind)| Column::new(format!("{prefix}_{joint}"), unit.of(*kind))).collect()
    }

    /// The columns of a reference trajectory, `t q q̇ q̈` (`hya excite`'s rows, `hya track`'s
    /// input).
    pub fn reference(&self) -> Vec<Column> {
        [
            vec![time()],
            self.columns("q", Unit::Position),
            self.columns("qd", Unit::Velocity),
            self.columns("qdd", Unit::Acceleration),
        ]
        .concat()
    }

    /// One column per pair of joints, row-major (`prefix_I_J`), in the unit `unit(i, j)` of
    /// joints `i` and `j`.
    pub fn pairs(&self, prefix: &str, unit: impl Fn(JointKind, JointKind) -> String) -> Vec<Column> {
        let mut columns = Vec::with_capacity(self.len() * self.len());
        for (row, row_kind) in &self.joints {
            for (column, column_kind) in &self.joints {
                columns.push(Column::new(format!("{prefix}_{row}_{column}"), unit(*row_kind, *column_kind)));
            }
        }
        columns
    }
}

/// The time column, `t [s]`.
pub fn time() -> Column {
    Column::new("t", "s")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_cells_split_into_name_and_unit() {
        assert_eq!(Column::from_header(" q_SAA [rad] "), Column::new("q_SAA", "rad"));
        assert_eq!(Column::from_header("tau1\t [N m]"), Column::new("tau1", "N m"));
        assert_eq!(Column::from_header("q[0]"), Column::bare("q[0]"), "an index is part of the name");
        assert_eq!(Column::from_header("t"), Column::bare("t"));
        assert_eq!(Column::from_header("[s]"), Column::bare("[s]"), "a unit alone is a name");
        assert_eq!(Column::new("q", "rad").to_string(), "q [rad]");
    }

    #[test]
    fn units_compare_without_blanks_and_product_signs() {
        assert!(same_unit("N m", "N·m") && same_unit("Nm", "N*m") && same_unit("rad/s²", "rad/s^2"));
        assert!(!same_unit("deg", "rad") && !same_unit("N", "N m"));
        let read = Column::from_header("q1 [deg]");
        assert!(!read.unit_fits(&Column::new("q1", "rad")));
        assert!(Column::bare("q1").unit_fits(&Column::new("q1", "rad")), "no unit given: nothing to check");
    }
}
