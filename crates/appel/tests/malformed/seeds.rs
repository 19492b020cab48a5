//! Small valid files of every format the readers take, written here so that the fuzzer needs no
//! data beside the repository. Each one uses as many of its format's features as fit in a few
//! hundred bytes, since a mutation can only reach the code that its seed reaches.

use std::io::{Cursor, Write};

/// A 4x4 RGBA PNG (textures and cut-outs).
pub fn png_rgba() -> Vec<u8> {
    let img = image::RgbaImage::from_fn(4, 4, |x, y| {
        image::Rgba([
            (x * 60) as u8,
            (y * 60) as u8,
            128,
            if x < 2 { 255 } else { 0 },
        ])
    });
    encode(
        image::DynamicImage::ImageRgba8(img),
        image::ImageFormat::Png,
    )
}

fn encode(img: image::DynamicImage, format: image::ImageFormat) -> Vec<u8> {
    let mut out = Cursor::new(Vec::new());
    img.write_to(&mut out, format).expect("encodes");
    out.into_inner()
}

/// One image per decoder: PNG (8-bit RGB, 16-bit grey, grey+alpha), JPEG, BMP, Radiance HDR,
/// OpenEXR (RGBA float and a lone Y channel) and PFM (colour little-endian, grey big-endian).
pub fn images() -> Vec<Vec<u8>> {
    let rgb = image::RgbImage::from_fn(5, 3, |x, y| image::Rgb([x as u8 * 40, y as u8 * 80, 7]));
    let grey16 = image::ImageBuffer::<image::Luma<u16>, _>::from_fn(3, 3, |x, y| {
        image::Luma([(x * 20000 + y * 1000) as u16])
    });
    let la = image::GrayAlphaImage::from_fn(2, 2, |x, _| image::LumaA([x as u8 * 200, 99]));
    let rgbf = image::Rgb32FImage::from_fn(4, 2, |x, y| image::Rgb([x as f32, y as f32, 0.5]));
    let mut exr_rgba = Cursor::new(Vec::new());
    {
        use exr::prelude::*;
        let layer = Layer::new(
            (3, 2),
            LayerAttributes::named("diffuse"),
            Encoding::FAST_LOSSLESS,
            SpecificChannels::rgba(|p: Vec2<usize>| (p.0 as f32, p.1 as f32, 0.25f32, 1.0f32)),
        );
        Image::from_layer(layer)
            .write()
            .to_buffered(&mut exr_rgba)
            .expect("exr");
    }
    let mut exr_y = Cursor::new(Vec::new());
    {
        use exr::prelude::*;
        let samples = FlatSamples::F16((0..4).map(|i| f16::from_f32(i as f32)).collect());
        let channels = AnyChannels::sort(SmallVec::from_vec(vec![AnyChannel::new("Y", samples)]));
        Image::from_layer(Layer::new(
            (2, 2),
            LayerAttributes::default(),
            Encoding::UNCOMPRESSED,
            channels,
        ))
        .write()
        .to_buffered(&mut exr_y)
        .expect("exr");
    }
    vec![
        png_rgba(),
        encode(rgb.clone().into(), image::ImageFormat::Png),
        encode(grey16.into(), image::ImageFormat::Png),
        encode(la.into(), image::ImageFormat::Png),
        encode(rgb.clone().into(), image::ImageFormat::Jpeg),
        encode(rgb.into(), image::ImageFormat::Bmp),
        encode(rgbf.into(), image::ImageFormat::Hdr),
        exr_rgba.into_inner(),
        exr_y.into_inner(),
        pfm(b"PF", 3, 2, true),
        pfm(b"Pf", 2, 2, false),
    ]
}

/// A portable float map of `w` by `h` pixels, little- or big-endian.
fn pfm(magic: &[u8], w: usize, h: usize, little: bool) -> Vec<u8> {
    let channels = if magic == b"PF" { 3 } else { 1 };
    let mut out = magic.to_vec();
    out.extend(format!("\n{w} {h}\n{}\n", if little { "-1.0" } else { "1.0" }).bytes());
    for i in 0..w * h * channels {
        let v = i as f32 * 0.25;
        out.extend(if little {
            v.to_le_bytes()
        } else {
            v.to_be_bytes()
        });
    }
    out
}

/// A unit square (a quad) and a triangle with normals, colours and a face property, in every PLY
/// encoding; the binary ones also carry an element the reader must skip, and a triangle strip.
pub fn ply() -> Vec<Vec<u8>> {
    let ascii = b"ply\nformat ascii 1.0\ncomment fuzz seed\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nelement face 2\nproperty list uchar int vertex_indices\nproperty int flags\nend_header\n0 0 0 0 0 1 0 0 255 0 0\n1 0 0 0 0 1 1 0 255 0 0\n1 1 0 0 0 1 1 1 255 0 0\n0 1 0 0 0 1 0 1 255 0 0\n0 0 1 0 0 1 0.5 0.5 0 0 255\n4 0 1 2 3 7\n3 0 1 4 9\n".to_vec();
    let strip = b"ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n5 0 1 2 3 -1\n".to_vec();
    vec![
        ascii,
        strip,
        ply_binary(false),
        ply_binary(true),
        ply_fast(),
    ]
}

fn put(out: &mut Vec<u8>, big: bool, bytes: &[u8]) {
    if big {
        out.extend(bytes.iter().rev());
    } else {
        out.extend(bytes);
    }
}

fn ply_binary(big: bool) -> Vec<u8> {
    let mut out = format!(
        "ply\nformat binary_{}_endian 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\nproperty float s\nproperty float t\nproperty ushort quality\nelement edge 1\nproperty list uchar short junk\nelement face 2\nproperty list ushort uint vertex_index\nproperty char flags\nend_header\n",
        if big { "big" } else { "little" }
    )
    .into_bytes();
    for (i, v) in [[0f64, 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]]
        .into_iter()
        .enumerate()
    {
        for x in v {
            put(&mut out, big, &x.to_le_bytes());
        }
        put(&mut out, big, &(v[0] as f32).to_le_bytes());
        put(&mut out, big, &(v[1] as f32).to_le_bytes());
        put(&mut out, big, &(i as u16 * 1000).to_le_bytes());
    }
    out.push(2);
    put(&mut out, big, &5i16.to_le_bytes());
    put(&mut out, big, &6i16.to_le_bytes());
    for face in [&[0u32, 1, 2][..], &[0, 2, 3]] {
        put(&mut out, big, &(face.len() as u16).to_le_bytes());
        for &i in face {
            put(&mut out, big, &i.to_le_bytes());
        }
        out.push(3);
    }
    out
}

/// The layout of most scans, which the reader takes on a fast path: float xyz, uchar/int faces.
fn ply_fast() -> Vec<u8> {
    let mut out = b"ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n".to_vec();
    for v in [[0f32, 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 1.]] {
        for x in v {
            out.extend(x.to_le_bytes());
        }
    }
    for f in [[0i32, 1, 2], [0, 2, 3]] {
        out.push(3);
        for i in f {
            out.extend(i.to_le_bytes());
        }
    }
    out
}

/// The MTL library the OBJ seeds name: every material statement and texture map Appel reads.
pub const MTL: &str = "# fuzz seed\nnewmtl red\nKa 0 0 0\nKd 0.8 0.1 0.1\nKs 0.2 0.2 0.2\nNs 50\nNi 1.45\nd 1\nillum 2\nmap_Kd -o 0.5 0 0 -s 2 2 1 tex.png\nmap_Ks tex.png\nmap_Ns tex.png\nmap_d -imfchan m tex.png\nbump -bm 0.5 tex.png\nnorm tex.png\n\nnewmtl glass\nKd 1 1 1\nTf 0.9 0.9 0.9\nTr 0.5\nNi 1.5\nillum 7\nKe 1 2 3\nmap_bump tex.png\n";

pub fn mtl() -> Vec<Vec<u8>> {
    vec![
        MTL.as_bytes().to_vec(),
        b"newmtl a\nKd 1 1 1\nmap_Kd ..\\textures\\TEX.PNG\nnewmtl b\nd 0.5\n".to_vec(),
    ]
}

/// OBJ seeds: every index form, negative indices, polygons (convex and concave), groups, smoothing,
/// materials from `m.mtl`, lines and points that are skipped.
pub fn obj() -> Vec<Vec<u8>> {
    let full = "# fuzz seed\nmtllib m.mtl\no thing\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nvn 0 1 0\ng front\nusemtl red\ns 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\ns off\nusemtl glass\nf -5//-2 -4//-2 -1//-1\nf 1/1 2/2 5/3\ng back\nusemtl missing\nf 1 3 5\nl 1 2\np 3\n";
    let concave = "v 0 0 0\nv 4 0 0\nv 4 4 0\nv 2 1 0\nv 0 4 0\nf 1 2 3 4 5\nf 1 \\\n 2 3\n";
    vec![full.as_bytes().to_vec(), concave.as_bytes().to_vec()]
}

/// The base64 of `bytes` (RFC 4648), for data URIs.
fn base64(bytes: &[u8]) -> String {
    const ABC: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(ABC[(n >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// Positions, normals, uvs (three vertices) and u16 indices for one triangle: 104 bytes.
fn gltf_buffer() -> Vec<u8> {
    let mut b = Vec::new();
    for v in [0f32, 0., 0., 1., 0., 0., 0., 1., 0.] {
        b.extend(v.to_le_bytes());
    }
    for v in [0f32, 0., 1., 0., 0., 1., 0., 0., 1.] {
        b.extend(v.to_le_bytes());
    }
    for v in [0f32, 0., 1., 0., 0., 1.] {
        b.extend(v.to_le_bytes());
    }
    for i in [0u16, 1, 2, 0] {
        b.extend(i.to_le_bytes());
    }
    b
}

/// The JSON of a glTF with every material input, extension, light and camera Appel reads;
/// `buffer_uri` is `None` in a GLB (its binary chunk).
fn gltf_json(buffer_uri: Option<&str>, image: &str) -> String {
    let uri = buffer_uri.map_or(String::new(), |u| format!(r#""uri": "{u}", "#));
    format!(
        r#"{{"asset": {{"version": "2.0"}},
"extensionsUsed": ["KHR_lights_punctual", "KHR_texture_transform", "KHR_materials_emissive_strength", "KHR_materials_ior", "KHR_materials_transmission", "KHR_materials_specular", "KHR_materials_clearcoat"],
"buffers": [{{{uri}"byteLength": 104}}],
"bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 36}},
  {{"buffer": 0, "byteOffset": 36, "byteLength": 36}},
  {{"buffer": 0, "byteOffset": 72, "byteLength": 24}},
  {{"buffer": 0, "byteOffset": 96, "byteLength": 6, "target": 34963}}],
"accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}},
  {{"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"}},
  {{"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"}},
  {{"bufferView": 3, "componentType": 5123, "count": 3, "type": "SCALAR"}}],
"images": [{image}],
"samplers": [{{"magFilter": 9729, "minFilter": 9987, "wrapS": 33648, "wrapT": 33071}}],
"textures": [{{"source": 0, "sampler": 0}}],
"materials": [{{"name": "all", "pbrMetallicRoughness": {{"baseColorFactor": [1, 0.5, 0.25, 1], "baseColorTexture": {{"index": 0, "texCoord": 0, "extensions": {{"KHR_texture_transform": {{"offset": [0.5, 0], "rotation": 0.3, "scale": [2, 2]}}}}}}, "metallicFactor": 0.5, "roughnessFactor": 0.25, "metallicRoughnessTexture": {{"index": 0}}}},
  "normalTexture": {{"index": 0, "scale": 0.8}}, "occlusionTexture": {{"index": 0, "strength": 0.5}}, "emissiveTexture": {{"index": 0}}, "emissiveFactor": [1, 1, 1],
  "alphaMode": "MASK", "alphaCutoff": 0.4, "doubleSided": true,
  "extensions": {{"KHR_materials_emissive_strength": {{"emissiveStrength": 3}}, "KHR_materials_ior": {{"ior": 1.4}}, "KHR_materials_transmission": {{"transmissionFactor": 0.5, "transmissionTexture": {{"index": 0}}}}, "KHR_materials_specular": {{"specularFactor": 0.7, "specularColorFactor": [1, 0.9, 0.8]}}, "KHR_materials_clearcoat": {{"clearcoatFactor": 1, "clearcoatRoughnessFactor": 0.1, "clearcoatTexture": {{"index": 0}}}}}}}},
  {{"alphaMode": "BLEND", "pbrMetallicRoughness": {{"baseColorFactor": [0, 1, 0, 0.5]}}}}],
"meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}}, "indices": 3, "material": 0, "mode": 4}},
  {{"attributes": {{"POSITION": 0}}, "material": 1}}]}}],
"cameras": [{{"type": "perspective", "perspective": {{"yfov": 0.8, "aspectRatio": 1.5, "znear": 0.1}}}},
  {{"type": "orthographic", "orthographic": {{"xmag": 1, "ymag": 1, "znear": 0, "zfar": 10}}}}],
"extensions": {{"KHR_lights_punctual": {{"lights": [{{"type": "point", "color": [1, 1, 1], "intensity": 10}},
  {{"type": "spot", "intensity": 5, "spot": {{"innerConeAngle": 0.1, "outerConeAngle": 0.5}}}}, {{"type": "directional", "range": 3}}]}}}},
"nodes": [{{"children": [1, 2, 3], "translation": [0, 0, -1], "rotation": [0, 0, 0, 1], "scale": [1, 2, 1]}},
  {{"mesh": 0, "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}},
  {{"camera": 0, "translation": [0, 0, 5]}},
  {{"extensions": {{"KHR_lights_punctual": {{"light": 1}}}}, "translation": [0, 3, 0]}},
  {{"mesh": 0, "translation": [2, 0, 0]}}, {{"camera": 1}}, {{"extensions": {{"KHR_lights_punctual": {{"light": 0}}}}}}],
"scene": 0, "scenes": [{{"nodes": [0, 4, 5, 6]}}]}}"#
    )
}

/// `.gltf` seeds: everything in one file (data URIs), and external buffer and image files.
pub fn gltf() -> Vec<Vec<u8>> {
    let data = format!(
        "data:application/octet-stream;base64,{}",
        base64(&gltf_buffer())
    );
    let png = format!(
        r#"{{"uri": "data:image/png;base64,{}"}}"#,
        base64(&png_rgba())
    );
    vec![
        gltf_json(Some(&data), &png).into_bytes(),
        gltf_json(Some("buffer.bin"), r#"{"uri": "tex.png"}"#).into_bytes(),
    ]
}

/// The files beside the external-reference glTF seed.
pub fn gltf_siblings() -> Vec<(&'static str, Vec<u8>)> {
    vec![("buffer.bin", gltf_buffer()), ("tex.png", png_rgba())]
}

/// A binary glTF: the JSON chunk, then the buffer with the PNG after the geometry as a buffer view.
pub fn glb() -> Vec<Vec<u8>> {
    let mut bin = gltf_buffer();
    let png = png_rgba();
    let png_offset = bin.len();
    bin.extend(&png);
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let json = gltf_json(
        None,
        r#"{"bufferView": 4, "mimeType": "image/png"}"#,
    )
    .replace(
        r#""target": 34963}],"#,
        &format!(
            r#""target": 34963}}, {{"buffer": 0, "byteOffset": {png_offset}, "byteLength": {}}}],"#,
            png.len()
        ),
    )
    .replace(
        r#""byteLength": 104}"#,
        &format!(r#""byteLength": {}}}"#, bin.len()),
    );
    let mut json = json.into_bytes();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::new();
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(&json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(&bin);
    vec![out]
}

/// The fenced ```toml blocks of a Markdown file.
fn fenced(markdown: &str, language: &str) -> Vec<Vec<u8>> {
    let open = format!("```{language}\n");
    markdown
        .split(&open)
        .skip(1)
        .filter_map(|rest| rest.split_once("\n```").map(|(block, _)| block))
        .map(|b| b.as_bytes().to_vec())
        .collect()
}

/// A path-traced scene using the files beside it: an OBJ mesh instanced twice, a bitmap texture,
/// an environment map.
const TOML_WITH_FILES: &str = r#"[camera]
eye = [0.0, 1.0, 4.0]
look_at = [0.0, 0.5, 0.0]
fov = 40.0
width = 32
height = 24

[render]
integrator = "path"
spp = 1
max_depth = 3

[materials.tex]
type = "diffuse"
reflectance = { type = "bitmap", file = "tex.png", filter = "nearest", wrap = "mirror", to_uv = [[2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 1.0]] }

[materials.cut]
type = "mask"
opacity = { type = "bitmap", file = "tex.png", raw = true }
material = "tex"

[meshes.thing]
file = "mesh.obj"

[[instance]]
mesh = "thing"
material = "cut"
transform = { translate = [0.5, 0.0, 0.0] }

[[instance]]
mesh = "thing"
transform = { rotate = { axis = [0.0, 1.0, 0.0], degrees = 30.0 }, scale = 0.5 }

[[shape]]
type = "mesh"
file = "mesh.ply"
material = "tex"

[[light]]
type = "envmap"
file = "sky.hdr"
scale = 0.5
"#;

/// TOML scenes: the built-in ones, every example in the scene format's documentation, and one
/// that reads meshes and images.
pub fn toml() -> Vec<Vec<u8>> {
    let mut out: Vec<Vec<u8>> = appel::scene::builtin::BUILTIN_SCENES
        .iter()
        .map(|(_, _, text)| text.as_bytes().to_vec())
        .collect();
    out.extend(fenced(
        include_str!("../../../../docs/scene-format.md"),
        "toml",
    ));
    out.push(TOML_WITH_FILES.as_bytes().to_vec());
    out
}

/// The same scenes as JSON (the schema is one).
pub fn json() -> Vec<Vec<u8>> {
    toml()
        .iter()
        .filter_map(|t| {
            let value: toml::Value = toml::from_str(std::str::from_utf8(t).ok()?).ok()?;
            serde_json::to_vec_pretty(&value).ok()
        })
        .collect()
}

/// Files that the scene seeds refer to.
pub fn scene_siblings() -> Vec<(&'static str, Vec<u8>)> {
    let sky = image::Rgb32FImage::from_fn(8, 4, |x, y| image::Rgb([x as f32, y as f32, 1.0]));
    vec![
        ("tex.png", png_rgba()),
        ("sky.hdr", encode(sky.into(), image::ImageFormat::Hdr)),
        ("mesh.obj", obj()[0].clone()),
        ("m.mtl", MTL.as_bytes().to_vec()),
        ("mesh.ply", ply()[0].clone()),
        ("part.xml", XML_PART.as_bytes().to_vec()),
    ]
}

const XML_PART: &str = r#"<scene version="3.0.0">
    <bsdf type="roughconductor" id="metal">
        <string name="material" value="Au"/>
        <float name="alpha" value="0.2"/>
    </bsdf>
</scene>
"#;

/// Mitsuba 3 scenes: parameters, includes, references, every kind of property, transforms and
/// textures, shapes that are built in and read from files, area and environment emitters.
const XML_FULL: &str = r#"<?xml version="1.0"?>
<!-- a fuzz seed -->
<scene version="3.0.0">
    <default name="spp" value="4"/>
    <default name="res" value="24"/>
    <include filename="part.xml"/>
    <integrator type="path">
        <integer name="max_depth" value="4"/>
        <integer name="rr_depth" value="3"/>
    </integrator>
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <string name="fov_axis" value="smaller"/>
        <transform name="to_world">
            <lookat origin="0, 1, 4" target="0, 0.5, 0" up="0, 1, 0"/>
        </transform>
        <sampler type="independent">
            <integer name="sample_count" value="$spp"/>
        </sampler>
        <film type="hdrfilm">
            <integer name="width" value="$res"/>
            <integer name="height" value="$res"/>
            <rfilter type="gaussian"/>
        </film>
    </sensor>
    <texture type="bitmap" id="tex">
        <string name="filename" value="tex.png"/>
        <string name="filter_type" value="nearest"/>
        <string name="wrap_mode" value="clamp"/>
        <transform name="to_uv">
            <scale x="2" y="3"/>
        </transform>
    </texture>
    <bsdf type="twosided" id="white">
        <bsdf type="diffuse">
            <ref name="reflectance" id="tex"/>
        </bsdf>
    </bsdf>
    <bsdf type="dielectric" id="glass">
        <string name="int_ior" value="bk7"/>
        <float name="ext_ior" value="1.0"/>
    </bsdf>
    <bsdf type="plastic" id="plastic">
        <rgb name="diffuse_reflectance" value="0.1, 0.2, 0.3"/>
        <spectrum name="specular_reflectance" value="400:0.5, 700:0.9"/>
    </bsdf>
    <bsdf type="normalmap" id="bumpy">
        <texture name="normalmap" type="bitmap">
            <string name="filename" value="tex.png"/>
            <boolean name="raw" value="true"/>
        </texture>
        <bsdf type="principled">
            <rgb name="base_color" value="0.8"/>
            <float name="roughness" value="0.3"/>
            <float name="metallic" value="0.5"/>
        </bsdf>
    </bsdf>
    <shape type="rectangle">
        <transform name="to_world">
            <rotate x="1" angle="-90"/>
            <scale value="2"/>
        </transform>
        <ref id="white"/>
    </shape>
    <shape type="sphere">
        <point name="center" x="0" y="0.5" z="0"/>
        <float name="radius" value="0.5"/>
        <ref id="glass"/>
    </shape>
    <shape type="cube">
        <transform name="to_world">
            <matrix value="0.3 0 0 -1  0 0.3 0 0.3  0 0 0.3 0  0 0 0 1"/>
        </transform>
        <ref id="metal"/>
    </shape>
    <shape type="obj">
        <string name="filename" value="mesh.obj"/>
        <boolean name="face_normals" value="true"/>
        <ref id="bumpy"/>
    </shape>
    <shape type="ply">
        <string name="filename" value="mesh.ply"/>
        <transform name="to_world">
            <translate x="1"/>
        </transform>
        <bsdf type="blendbsdf">
            <texture name="weight" type="mesh_attribute">
                <string name="name" value="vertex_color"/>
            </texture>
            <ref id="plastic"/>
            <bsdf type="conductor"/>
        </bsdf>
    </shape>
    <shape type="disk">
        <transform name="to_world">
            <translate y="1.99"/>
        </transform>
        <emitter type="area">
            <rgb name="radiance" value="5, 4, 3"/>
        </emitter>
    </shape>
    <emitter type="envmap">
        <string name="filename" value="sky.hdr"/>
        <float name="scale" value="0.5"/>
    </emitter>
    <emitter type="point">
        <point name="position" value="0, 2, 1"/>
        <spectrum name="intensity" value="3"/>
    </emitter>
</scene>
"#;

const XML_SMALL: &str = r#"<scene version="2.1.0">
    <sensor type="perspective">
        <transform name="to_world"><lookat origin="0,0,3" target="0,0,0"/></transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
    </sensor>
    <shape type="sphere"><bsdf type="roughplastic"><float name="alpha" value="0.1"/></bsdf></shape>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <emitter type="spot"><float name="cutoff_angle" value="30"/><transform name="to_world"><translate z="2"/></transform></emitter>
</scene>
"#;

pub fn xml() -> Vec<Vec<u8>> {
    vec![
        XML_FULL.as_bytes().to_vec(),
        XML_SMALL.as_bytes().to_vec(),
        XML_PART.as_bytes().to_vec(),
    ]
}

/// Zip archives: a mesh with its material library and texture (deflated, in a folder), a GLB
/// stored without compression, and one with two meshes (which must be named).
pub fn zip() -> Vec<Vec<u8>> {
    let one = |files: &[(&str, &[u8])], stored: bool| {
        let mut out = Cursor::new(Vec::new());
        {
            let mut zip = zip::ZipWriter::new(&mut out);
            let method = if stored {
                zip::CompressionMethod::Stored
            } else {
                zip::CompressionMethod::Deflated
            };
            let options = zip::write::SimpleFileOptions::default().compression_method(method);
            zip.add_directory("model/", options).expect("zip");
            for (name, bytes) in files {
                zip.start_file(*name, options).expect("zip");
                zip.write_all(bytes).expect("zip");
            }
            zip.finish().expect("zip");
        }
        out.into_inner()
    };
    let obj = obj()[0].clone();
    let png = png_rgba();
    let glb = glb().remove(0);
    let ply = ply()[2].clone();
    vec![
        one(
            &[
                ("model/mesh.obj", &obj),
                ("model/m.mtl", MTL.as_bytes()),
                ("model/tex.png", &png),
            ],
            false,
        ),
        one(&[("thing.glb", &glb)], true),
        one(&[("a.ply", &ply), ("b/c.obj", &obj)], false),
    ]
}
