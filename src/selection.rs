//! A registered plug-in chosen with parameter values, written `name` or `name:key=value,key=value` (choices as
//! their words): one type for shadow methods (`measure --config`, the bench's rows) and eye transparency
//! techniques (`measure transparency --technique`, the transparency bench), parsed, labelled and looked up
//! through its family's registry.

use std::marker::PhantomData;

use crate::render::method::{ParamError, ParamSpec, ParamValues, UnknownName};
use anyhow::{Context, Result};

/// A registry of plug-ins with parameters.
pub trait Family {
    type Plugin: ?Sized + 'static;
    /// The plug-in called `name`, or an error listing the known names.
    fn find(name: &str) -> Result<&'static Self::Plugin, UnknownName>;
    fn name(plugin: &Self::Plugin) -> &'static str;
    /// The parameter `key` of `plugin`, or an error listing its parameters.
    fn spec(plugin: &Self::Plugin, key: &str) -> Result<&'static ParamSpec, ParamError>;
}

/// The shadow methods (`crate::methods::registry`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Methods;

impl Family for Methods {
    type Plugin = dyn crate::methods::ShadowMethod;
    fn find(name: &str) -> Result<&'static Self::Plugin, UnknownName> {
        crate::methods::registry::find(name)
    }
    fn name(plugin: &Self::Plugin) -> &'static str {
        plugin.name()
    }
    fn spec(plugin: &Self::Plugin, key: &str) -> Result<&'static ParamSpec, ParamError> {
        crate::methods::spec(plugin, key)
    }
}

/// The eye transparency techniques (`crate::render::transparency::registry`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Techniques;

impl Family for Techniques {
    type Plugin = dyn crate::render::transparency::EyeTransparency;
    fn find(name: &str) -> Result<&'static Self::Plugin, UnknownName> {
        crate::render::transparency::registry::find(name)
    }
    fn name(plugin: &Self::Plugin) -> &'static str {
        plugin.name()
    }
    fn spec(plugin: &Self::Plugin, key: &str) -> Result<&'static ParamSpec, ParamError> {
        crate::render::transparency::registry::spec(plugin, key)
    }
}

/// A plug-in of family `F` with parameter values (missing keys take their defaults).
#[derive(Clone, Debug, PartialEq)]
pub struct Selection<F> {
    pub name: String,
    pub params: ParamValues,
    family: PhantomData<F>,
}

/// `name` or `name:key=value,...` split into the name and its `(key, value)` pairs, each trimmed: the one reader
/// of that spelling (methods, techniques, motion and fur configurations). A pair without `=` is one error
/// naming `text`.
pub fn split_config(text: &str) -> Result<(&str, Vec<(&str, &str)>)> {
    let (name, rest) = text.split_once(':').unwrap_or((text, ""));
    let pairs = rest
        .split(',')
        .filter(|kv| !kv.trim().is_empty())
        .map(|kv| {
            kv.split_once('=')
                .map(|(k, v)| (k.trim(), v.trim()))
                .with_context(|| format!("'{text}': expected key=value in '{kv}'"))
        })
        .collect::<Result<_>>()?;
    Ok((name.trim(), pairs))
}

/// A shadow method with parameter values.
pub type MethodConfig = Selection<Methods>;
/// An eye transparency technique with parameter values.
pub type TechniqueConfig = Selection<Techniques>;

impl<F: Family> Selection<F> {
    pub fn new(name: impl Into<String>, params: ParamValues) -> Selection<F> {
        Selection {
            name: name.into(),
            params,
            family: PhantomData,
        }
    }

    /// `name` or `name:key=value,...`: the name must be registered and every value in its parameter's range.
    pub fn parse(text: &str) -> Result<Selection<F>> {
        let (name, pairs) = split_config(text)?;
        let plugin = F::find(name)?;
        let mut params = ParamValues::new();
        for (k, v) in pairs {
            let v = F::spec(plugin, k)
                .and_then(|s| s.parse(v))
                .map_err(|e| anyhow::anyhow!("'{text}': {e}"))?;
            params.insert(k.to_string(), v);
        }
        Ok(Selection::new(F::name(plugin), params))
    }

    /// `name` or `name:key=value,...` (choices as words), parseable by [`Selection::parse`].
    pub fn label(&self) -> String {
        if self.params.is_empty() {
            return self.name.clone();
        }
        format!("{}:{}", self.name, self.param_words().join(","))
    }

    /// Each parameter as `key=value`, as a person types it after `name:` (choices as words, `spacing=linear`).
    pub fn param_words(&self) -> Vec<String> {
        let plugin = F::find(&self.name).ok();
        self.params
            .iter()
            .map(|(k, v)| match plugin.and_then(|p| F::spec(p, k).ok()) {
                Some(s) => format!("{k}={}", s.format(*v)),
                None => format!("{k}={v}"),
            })
            .collect()
    }

    /// The registered plug-in.
    pub fn plugin(&self) -> Result<&'static F::Plugin> {
        Ok(F::find(&self.name)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn methods_and_techniques_parse_and_label_alike() {
        let m = MethodConfig::parse("dom:layers=3,spacing=uniform").unwrap();
        assert_eq!(m.params.get("layers"), Some(&3.0));
        assert_eq!(m.label(), "dom:layers=3,spacing=uniform");
        assert_eq!(MethodConfig::parse(&m.label()).unwrap(), m);
        let t = TechniqueConfig::parse("occupancy-order:precision=f16").unwrap();
        assert_eq!(t.label(), "occupancy-order:precision=f16");
        assert_eq!(TechniqueConfig::parse(&t.label()).unwrap(), t);
        let plain = crate::render::transparency::registry::default_technique().name();
        assert_eq!(TechniqueConfig::parse(plain).unwrap().label(), plain);
    }

    #[test]
    fn bad_selections_name_what_is_wrong() {
        let plain = crate::render::transparency::registry::default_technique().name();
        let e = MethodConfig::parse("nope").unwrap_err().to_string();
        assert!(e.starts_with("unknown shadow method 'nope' (known: "), "{e}");
        let e = MethodConfig::parse("dom:layers=99").unwrap_err().to_string();
        assert!(
            e.starts_with("'dom:layers=99': parameter 'layers' = 99 is out of range"),
            "{e}"
        );
        let e = TechniqueConfig::parse(&format!("{plain}:nokey=1"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(&format!("technique '{plain}' has no parameter 'nokey'")),
            "{e}"
        );
        let e = TechniqueConfig::parse(&format!("{plain}:x"))
            .unwrap_err()
            .to_string();
        assert_eq!(e, format!("'{plain}:x': expected key=value in 'x'"));
    }
}
