//! The one list of eye transparency techniques: settings validation, the renderer, the pipelines and the shader
//! tests go through it, so adding a technique is its own files plus one line here.

use super::EyeTransparency;
use super::wboit::Wboit;

static TECHNIQUES: &[&dyn EyeTransparency] = &[&Wboit];

/// Every registered technique, in UI order.
pub fn all() -> &'static [&'static dyn EyeTransparency] {
    TECHNIQUES
}

/// The technique called `name`, or an error listing the known names.
pub fn find(name: &str) -> Result<&'static dyn EyeTransparency, String> {
    TECHNIQUES
        .iter()
        .copied()
        .find(|t| t.name() == name)
        .ok_or_else(|| {
            let names: Vec<_> = TECHNIQUES.iter().map(|t| t.name()).collect();
            format!(
                "unknown eye transparency technique '{name}' (known: {})",
                names.join(", ")
            )
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unknown_name_is_an_error_listing_the_known_names() {
        assert_eq!(
            find("sorted").err().as_deref(),
            Some("unknown eye transparency technique 'sorted' (known: wboit)")
        );
        assert_eq!(
            find("").err().as_deref(),
            Some("unknown eye transparency technique '' (known: wboit)")
        );
    }

    #[test]
    fn every_technique_is_found_by_its_unique_kebab_case_name() {
        let mut names = Vec::new();
        for t in all() {
            let name = t.name();
            assert!(
                !name.is_empty() && name.chars().all(|c| c.is_ascii_lowercase() || c == '-'),
                "{name}: names are kebab-case"
            );
            assert!(!names.contains(&name), "{name}: registered twice");
            assert_eq!(find(name).map(|f| f.name()), Ok(name));
            names.push(name);
        }
        assert_eq!(names, ["wboit"]);
    }

    #[test]
    fn the_default_setting_is_registered() {
        let default = crate::render::RenderSettings::default().transparency;
        assert_eq!(default, "wboit");
        assert!(find(&default).is_ok());
    }
}
