//! Settings chosen by name — `index.measure: dynamic`, `norm: rms`, `format: graspgen` — and
//! the one table of their spellings.
//!
//! Each such setting is an enum that implements [`Spelled`] through the crate's `spelled!` macro, which
//! declares every value's spelling once, beside the enum. The task-file loader, the Python
//! bindings and the command line read names with [`Spelled::from_name`] and list them in their
//! messages with [`Spelled::spellings`]; the Python stub's `Literal` types and the docs are
//! checked against [`Spelled::names`] by tests.

/// A setting chosen by name. Implemented by the crate's `spelled!` macro.
pub trait Spelled: Sized + Copy + PartialEq + 'static {
    /// Every value, in the order the docs list them.
    const ALL: &'static [Self];

    /// The value's spelling, as it is written in a task file and read back.
    fn as_str(self) -> &'static str;

    /// Other spellings read as this value (e.g. `anygrasp` for the GraspNet format); never
    /// written.
    fn aliases(self) -> &'static [&'static str] {
        &[]
    }

    /// The value spelled `name` (its spelling or one of its aliases), if any.
    fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .iter()
            .copied()
            .find(|value| value.as_str() == name || value.aliases().contains(&name))
    }

    /// Every value's spelling, in the order of [`Spelled::ALL`].
    fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|value| value.as_str()).collect()
    }

    /// Every spelling for messages, comma-separated, each value's aliases in parentheses
    /// after it: `graspnet (anygrasp)`.
    fn spellings() -> String {
        Self::ALL
            .iter()
            .map(|value| match value.aliases() {
                [] => value.as_str().to_string(),
                aliases => format!("{} ({})", value.as_str(), aliases.join(", ")),
            })
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// Reads `name`, or says which spellings are accepted: `'{name}' is not one of …`.
    fn parse(name: &str) -> Result<Self, String> {
        Self::from_name(name).ok_or_else(|| format!("'{name}' is not one of {}", Self::spellings()))
    }
}

/// Implements [`Spelled`] for a field-less enum from its spelling table:
///
/// ```ignore
/// spelled!(Norm { Rms => "rms", L2 => "l2", L1 => "l1" });
/// spelled!(GraspFormat { Graspath => "graspath", GraspNet => "graspnet" | "anygrasp" });
/// ```
///
/// The order of the table is [`Spelled::ALL`]'s; spellings after `|` are aliases.
macro_rules! spelled {
    ($enum:ident { $($variant:ident => $name:literal $(| $alias:literal)*),+ $(,)? }) => {
        impl $crate::spelling::Spelled for $enum {
            const ALL: &'static [Self] = &[$(Self::$variant),+];

            fn as_str(self) -> &'static str {
                match self {
                    $(Self::$variant => $name),+
                }
            }

            fn aliases(self) -> &'static [&'static str] {
                match self {
                    $(Self::$variant => &[$($alias),*]),+
                }
            }
        }
    };
}
pub(crate) use spelled;

#[cfg(test)]
mod tests {
    use super::Spelled;

    #[derive(Debug, Clone, Copy, PartialEq)]
    enum Fruit {
        Apple,
        Pear,
    }
    spelled!(Fruit { Apple => "apple", Pear => "pear" | "poire" | "birne" });

    #[test]
    fn every_spelling_and_alias_reads_back() {
        assert_eq!(Fruit::ALL, &[Fruit::Apple, Fruit::Pear]);
        for fruit in Fruit::ALL {
            assert_eq!(Fruit::from_name(fruit.as_str()), Some(*fruit));
            for alias in fruit.aliases() {
                assert_eq!(Fruit::from_name(alias), Some(*fruit));
            }
        }
        assert_eq!(Fruit::from_name("Apple"), None);
        assert_eq!(Fruit::from_name(""), None);
        assert_eq!(Fruit::names(), ["apple", "pear"]);
    }

    #[test]
    fn messages_list_every_spelling() {
        assert_eq!(Fruit::spellings(), "apple, pear (poire, birne)");
        assert_eq!(
            Fruit::parse("plum"),
            Err("'plum' is not one of apple, pear (poire, birne)".to_string())
        );
        assert_eq!(Fruit::parse("birne"), Ok(Fruit::Pear));
    }
}
