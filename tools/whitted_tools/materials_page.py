"""docs/MATERIALS.md: the material gallery (whitted_tools gallery-materials) and the material
cost benchmark (whitted_tools bench-materials), from the results each Blender wrote under
OUT/images/materials/ (no bpy)."""

import json
from pathlib import Path

from whitted_tools.pages import table, write_page
from whitted_tools.verbs import blender_line, python_line

TARGET_SSIM = 0.95
TARGET_RATIO = (0.95, 1.05)
CYCLES_SAMPLES = 256  # all at the pixel centre (filter 0.01): glass's random choices average
GALLERY_COMMANDS = (
    blender_line("gallery-materials", "--out", "docs"),
    python_line("gallery-materials", "--out", "docs"),
)

# Real models made by other people, as Debian's assimp-testmodels installs them.
THIRD_PARTY_MODELS = Path("/usr/share/assimp/models")
THIRD_PARTY_PACKAGE = "assimp-testmodels (Debian 12)"
# As /usr/share/doc/assimp-testmodels/copyright states it for these files ("Files: *").
THIRD_PARTY_LICENCE = "BSD-3-clause, 2006-2022 ASSIMP Development Team"
THIRD_PARTY = [
    {
        "scene": "box_textured",
        "file": "glTF2/BoxTextured-glTF/BoxTextured.gltf",
        "differs": "The glTF default roughness 1 on a dielectric: its specular layer is "
        "a GGX lobe of roughness 1 since the Blender local model (issue 29; 3.4's ratio "
        "0.946 -> 0.987, 5.0's 0.981 -> 0.955 while the layer dimmed the base by its "
        "Fresnel factor at the view, 1.000 with the layer's albedo). Before: Cycles 3.x's "
        "Burley diffuse since 9993313 (0.855 -> 0.946).",
    },
    {
        "scene": "clearcoat_test",
        "file": "glTF2/ClearCoat-glTF/ClearCoatTest.gltf",
        "differs": "KHR_materials_clearcoat as Principled Coat: the coat is a GGX lobe of "
        "its roughness, blurring what it mirrors, since the Blender local model (issue "
        "29: 3.4's ratio 0.844 -> 0.988, 5.0's 0.866 -> 0.984); the 'Coating Only' "
        "column (black, roughness 0.03) mirrors the floor as Cycles does since the "
        "dielectric specular layer (docs/SUPPORT.md; before, it was black). Its labels "
        "are emissive textures: since emissive meshes are lights (9 objects, 36 "
        "triangles) they light the floor beside them as in Cycles; SSIM 0.989 -> 0.982 "
        "(3.4) and 0.988 -> 0.981 (5.0), the feelers' noise at one sample per pixel.",
    },
    {
        "scene": "texture_transform",
        "file": "glTF2/textureTransform/TextureTransformTest.gltf",
        "differs": "KHR_texture_transform (a Mapping node) renders as Cycles does; it was "
        "falsely warned as not supported. The rough specular layer as box_textured's "
        "(3.4's ratio 0.954 -> 0.986).",
    },
    {
        "scene": "two_cylinder_engine",
        "file": "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
        "differs": "Rough dielectrics, as box_textured (3.4's ratio 0.969 -> 0.992, 5.0's "
        "0.996 -> 0.999). A few zero-area triangles are skipped, with a warning.",
    },
    {
        "scene": "specular_glossiness_box",
        "file": "glTF2/BoxTextured-glTF-pbrSpecularGlossiness/BoxTextured.gltf",
        "differs": "KHR_materials_pbrSpecularGlossiness: the two Blenders' importers "
        "build different graphs for it, hence different figures; the 5.0 difference "
        "was not examined further.",
    },
    {
        "scene": "spider_obj",
        "file": "OBJ/spider.obj",
        "differs": "OBJ + MTL with JPEG textures: matches.",
    },
    {
        "scene": "duck_dae",
        "file": "Collada/duck.dae",
        "differs": "3.4 only (5.0 has no Collada importer). The importer makes a Principled "
        "of Metallic 0.5, Roughness 0.5: its metal half and specular layer are GGX "
        "lobes since the Blender local model (issue 29; ratio 0.825 -> 0.994). Before, "
        "Phong lobes: 0.692, Burley's diffuse (9993313) 0.697, the Phong exponent as a "
        "quarter of the Blinn one (c43f207) 0.825.",
    },
]

KNOWN_DIFFERENCES = [
    "## Known differences",
    "",
    "- **hdri_mirror_glass**: the glass ball casts a full shadow in both (Render > Whitted >",
    "  Glass Shadows, Opaque by default, as Cycles' shadow rays stop at glass); Tinted",
    "  would let Whitted's feelers through weighted by the glass's transmissivity, a",
    "  lighter shadow than Cycles'. Cycles' glass keeps some noise at these samples.",
    "- **normal_mapped**: the diffuse lobe under the mapped normal fades towards the",
    "  plane's horizon as Cycles fades it (3.x: Chiang et al.'s bump shadowing term, 5.0:",
    "  Conty Estevez et al.'s); without that Whitted was 28% too bright in 3.4. 3.4's",
    "  Principled diffuse is Burley's, as Cycles 3.x's (ratio 0.963 -> 0.976); what is",
    "  left is Cycles' GGX highlight against Whitted's Phong one (a Diffuse BSDF plane",
    "  matches).",
    "- **bump_mapped** and **coat** are diffuse under their bumps and coats (no",
    "  specular layer of the base's own): a Phong highlight is not Cycles' GGX one",
    "  (see gltf_round_trip), and a rough coat does not blur what it reflects.",
    "",
]


def _runs(base, pattern):
    return [json.loads(path.read_text(encoding="utf-8")) for path in sorted(base.glob(pattern))]


def write_markdown(out_dir):
    """Rewrite OUT/MATERIALS.md from every Blender's gallery results and cost runs."""
    base = Path(out_dir) / "images" / "materials"
    lines = [
        "# Materials: Whitted beside Cycles",
        "",
        "Generated by `python -m whitted_tools gallery-materials`; do not edit. Real material",
        "set-ups (docs/SUPPORT.md lists how each node is read), **Whitted on the left, Cycles on",
        "the right**, over a mid grey where the film is transparent. Cycles: direct light",
        f"plus glossy and transmission bounces (no diffuse bounce), {CYCLES_SAMPLES} samples",
        "all at the pixel centre, no denoising, no caustics; the world does not light",
        "diffuse surfaces (Ray Visibility > Diffuse off). Whitted: one sample at each",
        "pixel centre, depth 8. Measured on the linear renders: **SSIM** (sRGB, clipped",
        "to [0, 1]) and **ratio**, the median over object pixels (covered in both, lit",
        "in Cycles, the floor left out) of the luminance ratio Whitted / Cycles. Targets: "
        f"SSIM >= {TARGET_SSIM}, ratio {TARGET_RATIO[0]}..{TARGET_RATIO[1]}.",
        "",
        "Regenerate:",
        "",
        *(f"    {command}" for command in GALLERY_COMMANDS),
        "",
        *KNOWN_DIFFERENCES,
        *_cost_lines(base),
    ]
    for results_path in sorted(base.glob("blender-*/results.json")):
        blender = results_path.parent.name
        results = json.loads(results_path.read_text(encoding="utf-8"))
        worst_ssim = min(r["ssim"] for r in results)
        worst_ratio = max((r["ratio"] for r in results), key=lambda r: abs(r - 1.0))
        rows = [
            (
                r["scene"],
                f"{r['ssim']:.3f}",
                f"{r['ratio']:.3f}",
                "yes" if r["passed"] else "**no**",
            )
            for r in results
        ]
        lines += [
            f"## {blender}",
            "",
            f"Worst SSIM {worst_ssim:.3f}; ratio furthest from 1: {worst_ratio:.3f}.",
            "",
            *table(("scene", "SSIM", "ratio", "targets met"), rows, align="lrrl"),
            "",
        ]
        for r in results:
            lines += [
                f"### {r['scene']} ({blender})",
                "",
                f"![{r['scene']}](images/materials/{blender}/{r['scene']}.png)",
                "",
            ]
    lines += _third_party_lines(base)
    write_page(Path(out_dir) / "MATERIALS.md", lines)


def _third_party_lines(base):
    """The third-party section: per file its source, licence, figures per Blender and
    what still differs, then the images."""
    runs = {
        path.parent.name: {r["scene"]: r for r in json.loads(path.read_text(encoding="utf-8"))}
        for path in sorted(base.glob("blender-*/third_party.json"))
    }
    if not runs:
        return []
    blenders = list(runs)
    header = ("scene", "file", *(f"SSIM / ratio {b}" for b in blenders))
    rows = []
    for entry in THIRD_PARTY:
        figures = []
        for blender in blenders:
            r = runs[blender].get(entry["scene"])
            figures.append("-" if r is None else f"{r['ssim']:.3f} / {r['ratio']:.3f}")
        rows.append((entry["scene"], f"`{entry['file']}`", *figures))
    lines = [
        "## Third-party scenes",
        "",
        f"Real models made by other people, from Debian's {THIRD_PARTY_PACKAGE} (under",
        f"`{THIRD_PARTY_MODELS}`; licence as the package's copyright file states it:",
        f"{THIRD_PARTY_LICENCE}). Each is imported with Blender's own importer (glTF,",
        "OBJ, Collada), its own lights and cameras removed, framed by a camera fitting",
        "its bounds, on a floor just under it, under the gallery's sun and black world;",
        "rendered and measured as the scenes above (SSIM / ratio; '-': not imported by",
        "that Blender).",
        "",
        *table(header, rows, align="ll" + "r" * len(blenders)),
        "",
        "What still differs, and why:",
        "",
        *(f"- **{entry['scene']}**: {entry['differs']}" for entry in THIRD_PARTY),
        "",
    ]
    for entry in THIRD_PARTY:
        for blender in blenders:
            if entry["scene"] in runs[blender]:
                lines += [
                    f"### {entry['scene']} ({blender})",
                    "",
                    f"![{entry['scene']}](images/materials/{blender}/{entry['scene']}.png)",
                    "",
                ]
    return lines


def _cost_lines(base):
    """The Cost section from whitted_tools bench-materials's results, if it ran."""
    runs = _runs(base, "cost-*.json")
    if not runs:
        return []
    first = runs[0]
    rows = []
    for run in runs:
        best = run["best"]
        share = (best["textured"] - best["constant"]) / best["textured"]
        rows.append(
            (
                run["blender"],
                f"{best['constant']:.3f}",
                f"{best['program']:.3f}",
                f"{best['textured']:.3f}",
                f"{run['program_over_constant']:.3f}",
                f"{share:.0%}",
            )
        )
    header = (
        "Blender",
        "constant (s)",
        "program (s)",
        "textured (s)",
        "program / constant",
        "textured share of trace",
    )
    return [
        "## Cost",
        "",
        "From `python -m whitted_tools bench-materials`: "
        f"{first['spheres']} smooth spheres on a floor, "
        f"{first['resolution'][0]}x{first['resolution'][1]}, {first['aa_samples']} samples "
        "per pixel, one sun; the spheres' material is in turn a constant Principled BSDF "
        "(no program), the same values computed per hit by a program (Base Color through "
        "an op that does not fold), and texture-heavy (images on Base Color and Roughness, "
        "a tangent-space normal map, a Noise texture mixed into the colour); "
        f"{first['repeats']} interleaved renders of each, best trace time. The textured "
        "share is (textured - constant) / textured: what the program and its texture "
        "reads add to the trace.",
        "",
        "Regenerate (the machine is shared: figures are of one run):",
        "",
        *(f"    {command}" for command in first["commands"]),
        "",
        *table(header, rows),
        "",
    ]
