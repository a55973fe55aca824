//! Module-scope named constants for the scene's material vectors, so that a union of
//! thousands of shapes names each material's albedo and phong vector instead of spelling its
//! four literals at every select (naga's parse of the 5 000-shape scene: 40% less time).

use crate::literal;
use sdfc_ir::func::Func;
use sdfc_ir::ops::Op;
use sdfc_ir::scene::Material;
use sdfc_ir::value::Value;
use std::collections::{BTreeMap, BTreeSet};

/// The bits of a vec4 constant, as a map key.
type Key = [u32; 4];

/// Material vectors that the emitted functions use, by value, with their WGSL names.
#[derive(Default)]
pub struct Consts {
    names: BTreeMap<Key, String>,
    /// Declarations in material order.
    decls: Vec<(String, String)>,
}

fn key(v: &Value<f32>) -> Option<Key> {
    match v {
        Value::V4(a) => Some(a.map(f32::to_bits)),
        _ => None,
    }
}

/// A WGSL identifier for a material name, upper case like the shader's other constants:
/// `MATERIAL_` keeps it clear of keywords and of the shader's own names; characters other
/// than letters, digits and `_` (an anonymous colour is `color#N`) become `_`.
fn ident(name: &str, part: &str) -> String {
    let clean: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_uppercase()
            } else {
                '_'
            }
        })
        .collect();
    format!("MATERIAL_{clean}_{part}")
}

impl Consts {
    /// The named vectors of `materials` that any of `funcs` uses. Two materials with the same
    /// vector share the first one's name; a name taken twice after cleaning gets a number.
    pub fn of(materials: &[Material], funcs: &[&Func]) -> Consts {
        let mut used = BTreeSet::new();
        for f in funcs {
            for (_, n) in f.graph.nodes() {
                if let Op::Const(c) = n.op {
                    if let Some(k) = key(&c.to_value()) {
                        used.insert(k);
                    }
                }
            }
        }
        let mut out = Consts::default();
        let mut taken = BTreeSet::new();
        for m in materials {
            for (part, v) in [("ALBEDO", m.albedo()), ("PHONG", m.phong())] {
                let k = v.map(f32::to_bits);
                if !used.contains(&k) || out.names.contains_key(&k) {
                    continue;
                }
                let mut name = ident(&m.name, part);
                let base = name.clone();
                let mut n = 2;
                while !taken.insert(name.clone()) {
                    name = format!("{base}{n}");
                    n += 1;
                }
                out.decls
                    .push((name.clone(), literal::value(&Value::V4(v))));
                out.names.insert(k, name);
            }
        }
        out
    }

    /// A vec4 constant by its bits: its name where it has one, else its literal.
    pub fn spell_v4(&self, bits: &Key) -> String {
        self.names
            .get(bits)
            .cloned()
            .unwrap_or_else(|| literal::value(&Value::V4(bits.map(f32::from_bits))))
    }

    /// The name of a constant, where it is a material vector.
    pub fn name(&self, v: &Value<f32>) -> Option<&str> {
        key(v).and_then(|k| self.names.get(&k)).map(String::as_str)
    }

    /// The declarations, one `const` per line.
    pub fn declarations(&self) -> String {
        self.decls
            .iter()
            .map(|(name, value)| format!("const {name}: vec4<f32> = {value};\n"))
            .collect()
    }

    pub fn is_empty(&self) -> bool {
        self.decls.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn material(name: &str, color: [f32; 3]) -> Material {
        Material {
            name: name.into(),
            color,
            ..Material::default()
        }
    }

    #[test]
    fn used_vectors_get_one_name_each() {
        let src = "material red { color: [1, 0, 0] }\n\
                   material Red { color: [0, 1, 0] }\n\
                   material same { color: [1, 0, 0] }\n\
                   scene = union(sphere(1).material(red), box(1).material(Red).translate([3, 0, 0]),\n\
                   sphere(1).material(same).translate([-3, 0, 0]), color(torus(1, 0.2), [0, 0, 1]));";
        let compiled = crate::compile(src, &crate::Options::default()).unwrap();
        let wgsl = &compiled.wgsl;
        // `red` and `Red` clean to the same name; the second is numbered.
        assert!(
            wgsl.contains("const MATERIAL_RED_ALBEDO: vec4<f32> = vec4<f32>(1.0, 0.0, 0.0, 0.0);"),
            "{wgsl}"
        );
        assert!(
            wgsl.contains("const MATERIAL_RED_ALBEDO2: vec4<f32> = vec4<f32>(0.0, 1.0, 0.0, 0.0);"),
            "{wgsl}"
        );
        // `same` has red's albedo: it shares red's name rather than declaring it twice.
        assert!(!wgsl.contains("MATERIAL_SAME_ALBEDO"), "{wgsl}");
        // An anonymous colour's `#` is not an identifier character.
        assert!(
            wgsl.contains(
                "const MATERIAL_COLOR_0_ALBEDO: vec4<f32> = vec4<f32>(0.0, 0.0, 1.0, 0.0);"
            ),
            "{wgsl}"
        );
        // Every phong vector is the default one, declared once.
        assert_eq!(wgsl.matches("_PHONG: vec4<f32>").count(), 1, "{wgsl}");
        // No material vector is spelled out where it is used.
        let body = &wgsl[wgsl.find("fn scene_material").unwrap()..];
        assert!(!body.contains("vec4<f32>(1.0, 0.0, 0.0, 0.0)"), "{body}");
    }

    #[test]
    fn unused_materials_are_not_declared() {
        let used = Consts::of(&[material("red", [1.0, 0.0, 0.0])], &[]);
        assert!(used.is_empty());
        assert_eq!(used.declarations(), "");
    }
}
