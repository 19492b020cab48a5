//! The XML layer as a whole: substitution, includes, paths, references, properties, errors.

use super::*;
use glam::DVec3;
use std::path::Path;

fn doc(text: &str) -> crate::error::Result<Document> {
    document_from_str(text, Path::new("scene.xml"), &XmlOptions::default())
}

fn doc_with(text: &str, params: &[(&str, &str)]) -> crate::error::Result<Document> {
    let options = XmlOptions {
        params: params
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect(),
    };
    document_from_str(text, Path::new("scene.xml"), &options)
}

fn err(text: &str) -> String {
    doc(text).unwrap_err().to_string()
}

fn first(d: &Document) -> std::rc::Rc<Object> {
    d.target(&d.root.children[0]).unwrap()
}

#[test]
fn defaults_are_substituted_and_overridden_by_parameters() {
    let text = r#"<scene version="3.0.0">
        <default name="spp" value="32"/>
        <default name="s" value="7"/>
        <default name="integrator" value="direct"/>
        <integrator type="$integrator">
            <integer name="max_depth" value="$spp$s"/>
            <string name="label" value="\$spp costs $s"/>
        </integrator>
    </scene>"#;
    let d = doc(text).unwrap();
    let i = first(&d);
    assert_eq!(i.plugin, "direct");
    // `$spp` is replaced before `$s`, so it is not read as `$s` followed by "pp".
    assert_eq!(i.int("max_depth").unwrap(), Some(327));
    let d = doc_with(text, &[("integrator", "path"), ("s", "1")]).unwrap();
    let i = first(&d);
    assert_eq!(i.plugin, "path");
    assert_eq!(i.int("max_depth").unwrap(), Some(321));
    assert_eq!(i.string("label").unwrap(), Some("$spp costs 1"));
}

#[test]
fn an_unknown_parameter_is_an_error_at_its_element() {
    let e = err("<scene version=\"3.0.0\">\n  <integrator type=\"$nope\"/>\n</scene>");
    assert!(
        e.starts_with("scene.xml:2:3: <integrator type=\"$nope\">: undefined parameter $nope"),
        "{e}"
    );
    // A default applies only after it is declared.
    let e = err("<scene version=\"3.0.0\">\n<integer name=\"a\" value=\"$n\"/>\n<default name=\"n\" value=\"1\"/>\n</scene>");
    assert!(e.starts_with("scene.xml:2:1: "), "{e}");
}

#[test]
fn properties_are_typed() {
    let d = doc(r#"<scene version="3.0.0"><shape type="sphere">
        <float name="f" value=" -1.5e2 "/>
        <integer name="i" value="12"/>
        <boolean name="b" value="TRUE"/>
        <string name="s" value="a b"/>
        <point name="p" x="1" y="2" z="3"/>
        <vector name="v" value="4, 5,6"/>
        <vector name="u" value="7"/>
        <rgb name="c" value="0.1 0.2, 0.3"/>
        <rgb name="g" value="0.5"/>
        <spectrum name="k" value="6.15"/>
        <spectrum name="r" value="400:0.1, 700:0.9"/>
    </shape></scene>"#)
    .unwrap();
    let s = first(&d);
    assert_eq!(s.float("f").unwrap(), Some(-150.0));
    assert_eq!(s.int("i").unwrap(), Some(12));
    assert_eq!(
        s.float("i").unwrap(),
        Some(12.0),
        "an integer reads as a float"
    );
    assert_eq!(s.bool("b").unwrap(), Some(true));
    assert_eq!(s.string("s").unwrap(), Some("a b"));
    assert_eq!(s.vector("p").unwrap(), Some([1.0, 2.0, 3.0]));
    assert_eq!(s.vector("v").unwrap(), Some([4.0, 5.0, 6.0]));
    assert_eq!(s.vector("u").unwrap(), Some([7.0; 3]));
    let value = |n: &str| s.prop(n).unwrap().value.clone();
    assert_eq!(value("c"), Value::Rgb([0.1, 0.2, 0.3]));
    assert_eq!(value("g"), Value::Rgb([0.5; 3]));
    assert_eq!(value("k"), Value::Spectrum(Spectrum::Uniform(6.15)));
    assert_eq!(
        value("r"),
        Value::Spectrum(Spectrum::Pairs(vec![(400.0, 0.1), (700.0, 0.9)]))
    );
    assert!(s.float("missing").unwrap().is_none());
    let e = s.int("f").unwrap_err().to_string();
    assert!(
        e.starts_with("scene.xml:2:9: <float name=\"f\">: expected an <integer>"),
        "{e}"
    );
    s.finish().unwrap();
}

#[test]
fn bad_values_are_errors_with_lines() {
    let cases = [
        (
            "<float name=\"x\" value=\"1.2.3\"/>",
            "could not parse the number \"1.2.3\"",
        ),
        (
            "<integer name=\"x\" value=\"1.5\"/>",
            "could not parse the integer",
        ),
        (
            "<boolean name=\"x\" value=\"yes\"/>",
            "expected \"true\" or \"false\"",
        ),
        ("<rgb name=\"x\" value=\"1 2\"/>", "one or three numbers"),
        (
            "<point name=\"x\" x=\"1\" y=\"2\"/>",
            "missing attribute \"z\"",
        ),
        (
            "<vector name=\"x\" value=\"1\" x=\"1\"/>",
            "cannot be mixed",
        ),
        ("<spectrum name=\"x\" value=\"500:1\"/>", "at least two"),
        (
            "<spectrum name=\"x\" value=\"500:1, 400:2\"/>",
            "must increase",
        ),
        (
            "<spectrum name=\"x\" value=\"500-1, 600:2\"/>",
            "wavelength:value pairs",
        ),
        ("<float name=\"x\"/>", "missing attribute \"value\""),
        (
            "<float name=\"x\" value=\"1\" extra=\"2\"/>",
            "unexpected attribute \"extra\"",
        ),
        (
            "<float name=\"x\" value=\"1\"/><float name=\"x\" value=\"2\"/>",
            "given twice",
        ),
        ("<translate x=\"1\"/>", "only appear inside <transform>"),
        ("<blob/>", "unsupported XML element"),
        (
            "<transform name=\"t\"><rotate angle=\"3\"/></transform>",
            "axis is zero",
        ),
        (
            "<transform name=\"t\"><matrix value=\"1 2 3\"/></transform>",
            "16 or 9 numbers",
        ),
        (
            "<transform name=\"t\"><float name=\"a\" value=\"1\"/></transform>",
            "cannot appear inside <transform>",
        ),
        (
            "<transform name=\"t\"><lookat origin=\"0,0,0\" target=\"0,0,0\"/></transform>",
            "invalid lookat",
        ),
    ];
    for (inner, message) in cases {
        let text = format!(
            "<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n  {inner}\n</shape></scene>"
        );
        let e = err(&text);
        assert!(e.starts_with("scene.xml:3:"), "{inner}: {e}");
        assert!(e.contains(message), "{inner}: {e}");
    }
}

#[test]
fn transforms_compose_in_mitsubas_order() {
    let d = doc(r#"<scene version="3.0.0"><shape type="sphere">
        <transform name="to_world">
            <scale value="2"/>
            <rotate z="1" angle="90"/>
            <translate x="1" y="0" z="0"/>
        </transform>
        <transform name="to_uv"><scale x="25" y="25"/></transform>
    </shape></scene>"#)
    .unwrap();
    let s = first(&d);
    let m = s.transform("to_world").unwrap().unwrap();
    // (1, 0, 0) scaled to (2, 0, 0), turned to (0, 2, 0), moved to (1, 2, 0).
    assert!((m.transform_point3(DVec3::X) - DVec3::new(1.0, 2.0, 0.0)).length() < 1e-12);
    let uv = s.transform("to_uv").unwrap().unwrap();
    assert_eq!(uv.transform_point3(DVec3::ONE), DVec3::new(25.0, 25.0, 1.0));
}

#[test]
fn objects_nest_and_reference_each_other() {
    let d = doc(r#"<scene version="3.0.0">
        <shape type="obj"><ref id="later"/><ref name="named" id="later"/></shape>
        <bsdf type="twosided" id="later"><bsdf type="diffuse"/></bsdf>
        <alias id="later" as="other"/>
        <shape type="obj"><ref id="missing"/></shape>
    </scene>"#)
    .unwrap();
    let shape = first(&d);
    let target = d.target(&shape.children[0]).unwrap();
    assert_eq!(
        (target.class.as_str(), target.plugin.as_str()),
        ("bsdf", "twosided")
    );
    assert_eq!(
        shape.named_child("named").map(|c| c.name.clone()),
        Some(Some("named".into()))
    );
    assert!(std::rc::Rc::ptr_eq(&d.ids["other"], &d.ids["later"]));
    let dangling = d.target(&d.root.children[2]).unwrap();
    let e = d.target(&dangling.children[0]).unwrap_err().to_string();
    assert!(
        e.starts_with("scene.xml:5:27: <ref id=\"missing\">: no object has id"),
        "{e}"
    );
    let e = err("<scene version=\"3.0.0\">\n<bsdf type=\"diffuse\" id=\"a\"/>\n<bsdf type=\"diffuse\" id=\"a\"/>\n</scene>");
    assert!(
        e.starts_with(
            "scene.xml:3:1: <bsdf type=\"diffuse\">: duplicate id \"a\" (first at scene.xml:2:1)"
        ),
        "{e}"
    );
}

#[test]
fn finish_rejects_what_no_reader_took() {
    let d = doc("<scene version=\"3.0.0\">\n<bsdf type=\"diffuse\">\n<float name=\"roughness\" value=\"1\"/>\n</bsdf></scene>").unwrap();
    let e = first(&d).finish().unwrap_err().to_string();
    assert_eq!(
        e,
        "scene.xml:3:1: <float name=\"roughness\">: parameter \"roughness\" is not supported by <bsdf type=\"diffuse\">"
    );
    let d = doc("<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n<emitter type=\"area\"/>\n</shape></scene>").unwrap();
    let e = first(&d).finish().unwrap_err().to_string();
    assert!(
        e.starts_with("scene.xml:3:1: a nested <emitter type=\"area\"> is not supported"),
        "{e}"
    );
}

#[test]
fn the_root_needs_a_version() {
    assert!(err("<scene/>").contains("missing attribute \"version\""));
    assert!(err("<scene version=\"0.6.0\"/>").contains("older than 2.0.0"));
    assert!(err("<bsdf version=\"3.0.0\" type=\"diffuse\"/>").contains("must be <scene>"));
    doc("<scene version=\"2.1.0\"/>").unwrap();
}

/// Files in a temporary folder: `main.xml` includes a fragment through a `<path>`.
#[test]
fn includes_and_paths_resolve_like_mitsuba() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    std::fs::create_dir_all(root.join("scenes/fragments")).unwrap();
    std::fs::create_dir_all(root.join("common/meshes")).unwrap();
    std::fs::write(root.join("common/meshes/sphere.obj"), "").unwrap();
    std::fs::write(
        root.join("scenes/fragments/grid.xml"),
        "<scene version=\"2.0.0\">\n  <default name=\"spp\" value=\"128\"/>\n  <sampler type=\"independent\"><integer name=\"sample_count\" value=\"$spp\"/></sampler>\n  <shape type=\"obj\" id=\"s\"><string name=\"filename\" value=\"meshes/sphere.obj\"/></shape>\n</scene>",
    )
    .unwrap();
    std::fs::write(
        root.join("scenes/fragments/one.xml"),
        "<bsdf version=\"3.0.0\" type=\"diffuse\"/>",
    )
    .unwrap();
    let main = root.join("scenes/main.xml");
    std::fs::write(
        &main,
        "<scene version=\"3.0.0\">\n  <path value=\"../common\"/>\n  <default name=\"spp\" value=\"4\"/>\n  <include filename=\"fragments/grid.xml\"/>\n  <shape type=\"sphere\"><include filename=\"fragments/one.xml\"/></shape>\n</scene>",
    )
    .unwrap();
    let d = load_document(&main, &XmlOptions::default()).unwrap();
    // The included scene's children join the including scene, and its <default> loses to the
    // one already set.
    assert_eq!(d.root.children.len(), 3);
    let sampler = d.target(&d.root.children[0]).unwrap();
    assert_eq!(sampler.int("sample_count").unwrap(), Some(4));
    assert_eq!(d.ids["s"].plugin, "obj");
    // An included non-scene root is one object.
    let sphere = d.target(&d.root.children[2]).unwrap();
    assert_eq!(d.target(&sphere.children[0]).unwrap().plugin, "diffuse");
    // File names resolve with the main file's resolver: the <path> first, then its folder.
    assert_eq!(d.resolver.folders()[0], root.join("scenes/../common"));
    assert_eq!(
        d.resolver.resolve("meshes/sphere.obj"),
        Some(root.join("scenes/../common/meshes/sphere.obj"))
    );
    assert_eq!(
        d.resolver.resolve("main.xml"),
        Some(root.join("scenes/main.xml"))
    );

    // A missing include names the including element.
    std::fs::write(
        &main,
        "<scene version=\"3.0.0\">\n\n  <include filename=\"nope.xml\"/>\n</scene>",
    )
    .unwrap();
    let e = load_document(&main, &XmlOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with(&format!(
            "{}:3:3: <include>: included file \"nope.xml\" not found",
            main.display()
        )),
        "{e}"
    );
    // An error inside an included file names that file and line.
    std::fs::write(
        root.join("scenes/bad.xml"),
        "<scene version=\"3.0.0\">\n<float name=\"x\" value=\"oops\"/>\n</scene>",
    )
    .unwrap();
    std::fs::write(
        &main,
        "<scene version=\"3.0.0\"><include filename=\"bad.xml\"/></scene>",
    )
    .unwrap();
    let e = load_document(&main, &XmlOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with(&format!(
            "{}:2:1: <float name=\"x\">",
            root.join("scenes/bad.xml").display()
        )),
        "{e}"
    );
    // A file including itself stops.
    std::fs::write(
        &main,
        "<scene version=\"3.0.0\"><include filename=\"main.xml\"/></scene>",
    )
    .unwrap();
    let e = load_document(&main, &XmlOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("nested includes"), "{e}");
    // <path> must exist and sit at the top.
    std::fs::write(
        &main,
        "<scene version=\"3.0.0\">\n<path value=\"nowhere\"/></scene>",
    )
    .unwrap();
    let e = load_document(&main, &XmlOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with(&format!(
            "{}:2:1: <path>: folder \"nowhere\" not found",
            main.display()
        )),
        "{e}"
    );
    std::fs::write(
        &main,
        "<scene version=\"3.0.0\"><shape type=\"obj\"><path value=\".\"/></shape></scene>",
    )
    .unwrap();
    let e = load_document(&main, &XmlOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("direct child of the root"), "{e}");
}

#[test]
fn spectrum_files_are_read() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.spd"), "# comment\n400 0.5\n700 0.25\n").unwrap();
    let main = dir.path().join("m.xml");
    std::fs::write(&main, "<scene version=\"3.0.0\"><bsdf type=\"diffuse\"><spectrum name=\"reflectance\" filename=\"s.spd\"/></bsdf></scene>").unwrap();
    let d = load_document(&main, &XmlOptions::default()).unwrap();
    let b = first(&d);
    assert_eq!(
        b.prop("reflectance").unwrap().value,
        Value::Spectrum(Spectrum::Pairs(vec![(400.0, 0.5), (700.0, 0.25)]))
    );
}
