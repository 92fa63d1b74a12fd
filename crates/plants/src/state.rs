//! The named four-entry state of a plant: one definition of its array conversions for the
//! cart's and the arm's state types.

/// Defines a plant's named state `Name { a, b, c, d }` (fields in the order of the plant's
/// state vector) with `to_array`, `from_array`, `is_finite` and `From` both ways with
/// `[f64; 4]`; `$order` names the entries for the docs (e.g. `"[z, θ, ż, θ̇]"`). A plant's own
/// methods on its state go in an `impl` block of their own.
macro_rules! named_state {
    (
        $(#[$meta:meta])*
        pub struct $name:ident, $order:literal {
            $($(#[$field_meta:meta])* $field:ident,)*
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Default)]
        pub struct $name {
            $($(#[$field_meta])* pub $field: f64,)*
        }

        impl $name {
            #[doc = concat!("The state as `", $order, "`.")]
            pub fn to_array(self) -> [f64; 4] {
                [$(self.$field),*]
            }

            #[doc = concat!("The state from `", $order, "`.")]
            pub fn from_array(x: [f64; 4]) -> Self {
                let [$($field),*] = x;
                Self { $($field),* }
            }

            /// `true` if every component is finite.
            pub fn is_finite(&self) -> bool {
                self.to_array().iter().all(|v| v.is_finite())
            }
        }

        impl From<[f64; 4]> for $name {
            fn from(x: [f64; 4]) -> Self {
                Self::from_array(x)
            }
        }

        impl From<$name> for [f64; 4] {
            fn from(s: $name) -> Self {
                s.to_array()
            }
        }
    };
}

pub(crate) use named_state;
