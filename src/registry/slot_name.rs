//! The names of slots and instances. Most are written out; the elements of a MotionBASIC array
//! are named only when asked for (a message, a trace line, an export), so a `DIM A&(20000)`
//! costs no string per element when a machine loads.

use std::borrow::Cow;
use std::fmt;
use std::sync::Arc;

use super::ValueType;

/// The shape of a MotionBASIC array as the registry stores it: one slot per element, in
/// row-major order (last subscript fastest), every subscript from 0.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ArrayShape {
    /// The name as first written (`FLAG&`, `B$`).
    pub written: String,
    /// The upper bound of each subscript.
    pub bounds: Vec<u32>,
}

impl ArrayShape {
    /// Its number of elements.
    pub fn len(&self) -> usize {
        self.bounds.iter().map(|&n| n as usize + 1).product()
    }

    /// Whether it has no element (never, for bounds that were checked).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The subscripts of element `index`.
    pub fn subscripts(&self, mut index: usize) -> Vec<u32> {
        let mut subs = vec![0u32; self.bounds.len()];
        for (k, &b) in self.bounds.iter().enumerate().rev() {
            let n = b as usize + 1;
            subs[k] = (index % n) as u32;
            index /= n;
        }
        subs
    }

    /// The name of element `index`: `A(3)`, `B$(1,2)`.
    pub fn element(&self, index: usize) -> String {
        let mut name = String::with_capacity(self.written.len() + 8 * self.bounds.len());
        name.push_str(&self.written);
        name.push('(');
        for (k, s) in self.subscripts(index).into_iter().enumerate() {
            if k > 0 {
                name.push(',');
            }
            // Digit by digit: a traced write to an element names it, so this runs per write.
            let mut digits = [0u8; 10];
            let mut at = digits.len();
            let mut n = s;
            loop {
                at -= 1;
                digits[at] = b'0' + (n % 10) as u8;
                n /= 10;
                if n == 0 {
                    break;
                }
            }
            name.extend(digits[at..].iter().map(|&d| char::from(d)));
        }
        name.push(')');
        name
    }

    /// Whether its elements hold text (`B$`).
    pub fn is_text(&self) -> bool {
        self.written.ends_with('$')
    }
}

/// The key the registry finds an array by: its first element's name in lower case (`g(0,0)`
/// for `G` with two subscripts), the one name of the array it keeps.
pub fn array_key(written: &str, dimensions: usize) -> String {
    format!("{written}({})", vec!["0"; dimensions].join(",")).to_ascii_lowercase()
}

/// Whether a MotionBASIC variable or array element of this registry name holds a string.
pub fn is_text_name(name: &str) -> bool {
    name.split('(')
        .next()
        .is_some_and(|base| base.ends_with('$'))
}

/// A MotionBASIC variable the registry gives storage: a scalar by name, or an array, one slot
/// per element.
#[derive(Debug, Clone)]
pub enum BasicVar {
    /// A scalar variable, named as first written.
    Scalar(String, ValueType),
    /// An array and the type of its elements.
    Array(Arc<ArrayShape>, ValueType),
}

impl BasicVar {
    /// Its number of slots.
    pub fn len(&self) -> usize {
        match self {
            BasicVar::Scalar(..) => 1,
            BasicVar::Array(shape, _) => shape.len(),
        }
    }

    /// Whether it has no slot (an array without elements).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The name of a slot or an instance.
#[derive(Debug, Clone)]
pub enum SlotName {
    /// Written out: `Queue.0.QueueOffset`, `Var.Count`, `SPEED`.
    Text(String),
    /// Element `index` (row-major) of a MotionBASIC array, named when asked for.
    Element {
        /// The array.
        array: Arc<ArrayShape>,
        /// The element.
        index: u32,
    },
}

impl SlotName {
    /// The name.
    pub fn text(&self) -> Cow<'_, str> {
        match self {
            SlotName::Text(s) => Cow::Borrowed(s),
            SlotName::Element { array, index } => Cow::Owned(array.element(*index as usize)),
        }
    }

    /// Whether the name starts with `prefix` (an element's name is not made for it).
    pub fn starts_with(&self, prefix: &str) -> bool {
        match self {
            SlotName::Text(s) => s.starts_with(prefix),
            SlotName::Element { array, .. } if prefix.len() <= array.written.len() => {
                array.written.starts_with(prefix)
            }
            // Only a prefix that starts with the array's name can start an element's name.
            SlotName::Element { array, .. } => {
                prefix.starts_with(array.written.as_str()) && self.text().starts_with(prefix)
            }
        }
    }

    /// Whether this is the name of a MotionBASIC text variable or text array element (`N$`,
    /// `B$(2)`).
    pub fn is_text(&self) -> bool {
        match self {
            SlotName::Text(s) => is_text_name(s),
            SlotName::Element { array, .. } => array.is_text(),
        }
    }
}

impl fmt::Display for SlotName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.text())
    }
}

impl PartialEq<str> for SlotName {
    fn eq(&self, other: &str) -> bool {
        match self {
            SlotName::Text(s) => s == other,
            SlotName::Element { array, .. } => {
                other.starts_with(array.written.as_str()) && self.text() == other
            }
        }
    }
}

impl PartialEq<&str> for SlotName {
    fn eq(&self, other: &&str) -> bool {
        self == *other
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shape(written: &str, bounds: &[u32]) -> Arc<ArrayShape> {
        Arc::new(ArrayShape {
            written: written.into(),
            bounds: bounds.to_vec(),
        })
    }

    #[test]
    fn elements_are_named_row_major_from_zero() {
        let a = shape("G", &[2, 3]);
        assert_eq!(a.len(), 12);
        assert_eq!(a.element(0), "G(0,0)");
        assert_eq!(a.element(5), "G(1,1)");
        assert_eq!(a.element(11), "G(2,3)");
        let b = shape("FLAG&", &[20000]);
        assert_eq!(b.element(20000), "FLAG&(20000)");
        assert_eq!(shape("T", &[1, 1, 4]).element(13), "T(1,0,3)");
    }

    #[test]
    fn an_element_name_is_made_only_as_needed_and_compares_as_text() {
        let name = SlotName::Element {
            array: shape("B$", &[4]),
            index: 3,
        };
        assert_eq!(name.text(), "B$(3)");
        assert_eq!(name.to_string(), "B$(3)");
        assert!(name.is_text());
        assert!(name.starts_with("B$"));
        assert!(name.starts_with("B$(3"));
        assert!(!name.starts_with("B$(4"));
        assert!(name == *"B$(3)");
        assert!(name != *"B$(4)");
        let scalar = SlotName::Text("SPEED".into());
        assert!(!scalar.is_text());
        assert!(scalar == *"SPEED");
    }
}
