//! POV-Ray's words that mean something else here or nothing at all, each with how to write it in
//! raydiance: a user who knows POV-Ray gets an answer in its terms rather than a parser's.
//! (`docs/coming-from-povray.md` says the same at length.)

use super::dialect::Dialect;

/// `color` or `colour` in a `light_source`.
const LIGHT_COLOUR: &str = "a POV-Ray light's colour lights every distance alike; here a light \
     has `power rgb <r, g, b>`: its radiant intensity (W/sr), which falls off as 1/r² (at \
     distance d a surface receives power/d²)";

/// `color`/`colour` before a colour, outside a light.
const COLOUR: &str = "POV-Ray's way to begin a colour; here a colour is written `rgb <r, g, b>` \
     alone, e.g. `diffuse rgb <0.8, 0.2, 0.2>`";

/// What to write here instead of POV-Ray's `word`, when `word` is one of POV-Ray's that
/// raydiance does not have. `inside` is the construct whose block the word stands in.
pub fn advice(word: &str, inside: Option<&str>) -> Option<&'static str> {
    Some(match word {
        "color" | "colour" if inside == Some("light_source") => LIGHT_COLOUR,
        "color" | "colour" => COLOUR,
        "pigment" => {
            "POV-Ray's `pigment` is here the material's diffuse reflectance: \
             `material { diffuse rgb <r, g, b> }`, or a texture node in its place \
             (`diffuse checker { rgb 0, rgb 1 }`)"
        }
        "finish" => {
            "POV-Ray's `finish` is here the material itself: `material { diffuse rgb ... \
             specular rgb ...  roughness 0.2 }` (`specular` is mirror reflectance, `roughness` \
             blurs it, `fresnel` makes it depend on the angle); there is no `phong` or \
             `ambient`: highlights are reflections of the lights (`coat 1` puts a glossy plastic \
             coat over `diffuse`)"
        }
        "texture" => {
            "POV-Ray's `texture` is here `material { ... }`: `diffuse` takes a colour or a \
             texture node (`checker`, `stripes`, `gradient`, `noise`, `marble`, `wood`, \
             `image_map`, `mix`, `pattern`)"
        }
        "normal" => {
            "POV-Ray's `normal` (bump mapping) stands here in a material: \
             `material { diffuse rgb 0.8  normal { bumps 0.5  scale 0.1 } }`"
        }
        "interior" => {
            "POV-Ray's `interior { ior ... }` is here a material parameter: \
             `material { transmission rgb 1  ior 1.5 }`, and what fills it a medium in the \
             material: `medium { absorption rgb <...> scattering rgb <...> }`"
        }
        "fog" | "media" => {
            "a medium filling the scene is here `atmosphere { absorption rgb <...> scattering \
             rgb <...> emission rgb <...> }`; inside objects, `medium { ... }` in a material"
        }
        "phong" | "ambient" | "reflection" | "brilliance" | "metallic" => {
            "that is an item of POV-Ray's `finish`; here a material has `diffuse`, `specular` \
             (mirror reflectance), `transmission`, `ior`, `fresnel`, `roughness`, `coat` (a \
             glossy plastic coat), `coat_roughness` and `emission`, and light comes only from \
             lights, emitters and the background"
        }
        "sky_sphere" => {
            "POV-Ray's `sky_sphere` is read in `.pov` scenes; here the sky is a constant colour \
             that lights the scene: `settings { background rgb ... }`"
        }
        "background" if inside.is_none() => {
            "POV-Ray's `background { color ... }` is here a setting: \
             `settings { background rgb <r, g, b> }` (it lights the scene)"
        }
        "area_light" | "fade_distance" | "fade_power" | "looks_like" => {
            "raydiance's light_source is a point light, a `spotlight` or a `parallel` light; an \
             area light is any object whose material has `emission rgb <...>`"
        }
        "radiosity" => "global illumination is `settings { integrator path }`, the default",
        "photons" if inside != Some("settings") => {
            "photon mapping is `settings { integrator photon }` (or `sppm`), with `photons N` \
             among the settings"
        }
        "right" | "sky" | "direction" | "perspective" => {
            "raydiance's camera is a perspective camera given by `location`, `look_at`, `angle` \
             (horizontal, degrees) and `up`; the image's aspect ratio comes from `resolution`"
        }
        "hollow" | "no_shadow" | "no_image" | "no_reflection" | "double_illuminate" | "inverse"
        | "clipped_by" => {
            "this POV-Ray object modifier is not supported (an object here takes a material and \
             transforms)"
        }
        "#switch" | "#case" | "#range" | "#break" => {
            "POV-Ray's `#switch` is read in `.pov` scenes only; here write `#if (...) ... \
             #elseif (...) ... #else ... #end`"
        }
        _ => return None,
    })
}

/// The message for POV-Ray's `word` where a scene read in `dialect` cannot have it: in `.scn`
/// what to write instead (`advice`); in `.pov`, where the word is POV-Ray's own, only what is
/// not built (the `.scn` advice, "write `settings { background ... }`", would mislead there:
/// the syntax error names the word).
pub fn message_in(dialect: Dialect, word: &str, inside: Option<&str>) -> Option<String> {
    match dialect {
        Dialect::Scn => message(word, inside),
        Dialect::Pov if word == "mesh_camera" => Some(
            "`mesh_camera`: POV-Ray 3.7's camera whose rays leave the faces of meshes (for baking \
             textures) is not built in raydiance; its cameras are perspective, orthographic and \
             POV-Ray's wide projections"
                .to_string(),
        ),
        Dialect::Pov => None,
    }
}

/// The message for POV-Ray's `word`, if it is one of them.
pub fn message(word: &str, inside: Option<&str>) -> Option<String> {
    advice(word, inside).map(|advice| format!("`{word}`: {advice}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_light_colour_is_explained_as_power() {
        assert_eq!(advice("color", Some("light_source")), Some(LIGHT_COLOUR));
        assert_eq!(advice("colour", Some("material")), Some(COLOUR));
        assert!(advice("background", Some("settings")).is_none(), "it is ours there");
        assert!(advice("photons", Some("settings")).is_none(), "it is ours there");
        assert!(advice("photons", Some("sphere")).is_some());
        assert!(advice("sphere", None).is_none());
    }
}
