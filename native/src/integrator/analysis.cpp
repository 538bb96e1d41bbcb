#include "integrator/analysis.h"

#include <cstdio>
#include <string>
#include <utility>
#include <variant>

#include "integrator/passes.h"
#include "scene/mesh_light.h"

namespace whitted {
namespace {

// 4096 -> "4,096", as the report writes counts.
std::string thousands(size_t n) {
  const std::string digits = std::to_string(n);
  std::string out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

void decide(Effects* effects, uint32_t bit, bool on, std::string name, std::string why) {
  if (!on) effects->bits &= ~bit;
  effects->decisions.push_back({std::move(name), on, std::move(why)});
}

// Hair, curves and point clouds (Mesh::curves, Mesh::points): named with their counts.
EffectDecision strands(const CompiledScene& scene) {
  size_t objects = 0;
  size_t segments = 0;
  size_t points = 0;
  for (const CompiledScene::Instance& instance : scene.instances) {
    const Mesh& mesh = instance.mesh->mesh;
    objects += mesh.curves.segment_count() + mesh.points.count() > 0;
    segments += mesh.curves.segment_count();
    points += mesh.points.count();
  }
  if (objects == 0) return {"hair and points", false, "no hair, curves or point cloud"};
  return {"hair and points", true,
          thousands(objects) + (objects == 1 ? " object: " : " objects: ") + thousands(segments) +
              " curve segments, " + thousands(points) + " points"};
}

// The materials whose programs trace rays from the hits they shade (Ambient Occlusion and
// Bevel nodes', shader/program.h HitRays): named, as their rays cost.
EffectDecision program_rays(const CompiledScene& scene) {
  size_t materials = 0;
  for (const Material& m : scene.materials)
    materials += m.program != nullptr && m.program->traces();
  if (materials == 0) {
    return {"ray-traced nodes", false, "no material has an Ambient Occlusion or Bevel node"};
  }
  return {"ray-traced nodes", true,
          thousands(materials) + (materials == 1 ? " material traces" : " materials trace") +
              " rays from its hits (Ambient Occlusion, Bevel)"};
}

// Light linking and shadow linking (light.h): named when some emitter uses them.
EffectDecision light_linking(const CompiledScene& scene) {
  size_t lamps = 0;
  size_t emitters = 0;
  size_t receivers = 0;
  for (const Light& light : scene.lights) {
    lamps += light.light_sets != kAllLightSets || light.shadow_sets != kAllLightSets;
  }
  for (const CompiledScene::Instance& instance : scene.instances) {
    const InstanceLinks& links = instance.links;
    emitters += links.light_sets != kAllLightSets || links.shadow_sets != kAllLightSets;
    receivers += links.light_set != 0 || links.shadow_set != 0;
  }
  if (!scene.light_linking) {
    return {"light linking", false, "no light or emissive object links receivers or blockers"};
  }
  return {"light linking", true,
          thousands(lamps) + (lamps == 1 ? " light, " : " lights, ") + thousands(emitters) +
              (emitters == 1 ? " emissive object" : " emissive objects") + " linked; " +
              thousands(receivers) + (receivers == 1 ? " object" : " objects") +
              " in light or shadow sets"};
}

// The lamps whose shapes rays see (Light::visibility, intersect_light), and which rays.
EffectDecision lamps_seen(const CompiledScene& scene) {
  size_t lamps = 0;
  for (const Light& light : scene.lights) lamps += light.has_shape() && light.visibility != 0;
  if (lamps == 0) {
    return {"lamps seen by rays", false,
            "no area lamp or lamp with a radius is seen by camera, glossy or transmission rays"};
  }
  std::string rays;
  for (const auto& [bit, name] :
       {std::pair{kCameraRay, "camera"}, std::pair{kReflectionRay, "glossy"},
        std::pair{kRefractionRay, "transmission"}}) {
    if ((scene.lamps_visibility & bit) != 0) rays += (rays.empty() ? "" : ", ") + std::string(name);
  }
  return {"lamps seen by rays", true,
          thousands(lamps) + (lamps == 1 ? " lamp" : " lamps") + " seen by " + rays + " rays"};
}

// The lamps whose node trees run per feeler (Light::program): named, as each of their
// feelers runs the program.
EffectDecision lamp_programs(const CompiledScene& scene) {
  size_t lamps = 0;
  for (const Light& light : scene.lights) lamps += light.program != nullptr;
  if (lamps == 0) {
    return {"lamp node trees", false,
            "no lamp's emission varies over it (a constant tree is folded into its colour)"};
  }
  return {"lamp node trees", true,
          thousands(lamps) + (lamps == 1 ? " lamp runs its" : " lamps run their") +
              " node tree at each feeler and where rays see it (Light Falloff)"};
}

// The UDIM images the materials sample (a Texture whose image is udim): each tile is a
// picture of its own, looked up where its uv falls (scene/texture.h udim_point). Counted
// by texture (an image two nodes sample twice) and their tiles.
EffectDecision udim_images(const CompiledScene& scene) {
  size_t textures = 0;
  size_t tiles = 0;
  for (const std::shared_ptr<const Texture>& texture : scene.textures) {
    const auto* image = std::get_if<ImageTexture>(&texture->source);
    if (image == nullptr || !image->udim) continue;
    textures += 1;
    tiles += image->tiles.size();
  }
  if (textures == 0) return {"UDIM tiles", false, "no material samples a UDIM image"};
  return {"UDIM tiles", true,
          thousands(textures) + (textures == 1 ? " texture" : " textures") + " of " +
              thousands(tiles) + " tiles, each read where its uv falls"};
}

// The objects whose meshes enclose a medium (Material::participating, integrator/volume.h):
// their bounds without a surface (seen by no ray, in the BVH still) or glass with a volume;
// those with a medium a program drives (heterogeneous.h) counted apart.
// Volume objects (Instance::volume) are counted apart again, with their largest grid.
struct MediaObjects {
  size_t homogeneous = 0;
  size_t heterogeneous = 0;  // a program drives it, grids or not
  size_t grids = 0;          // of those, Volume objects
  glm::ivec3 largest{0};     // the Volume objects' grid of most voxels, a side
  size_t total() const { return homogeneous + heterogeneous; }
};
MediaObjects media_objects(const CompiledScene& scene) {
  MediaObjects objects;
  const auto voxels = [](const glm::ivec3& r) { return size_t(r.x) * size_t(r.y) * size_t(r.z); };
  for (const CompiledScene::Instance& instance : scene.instances) {
    if (instance.volume) {
      objects.grids += 1;
      for (int role = 0; role < kGridRoles; ++role) {
        const auto& grid = instance.volume->grid(static_cast<GridRole>(role));
        if (grid && voxels(grid->resolution()) > voxels(objects.largest)) {
          objects.largest = grid->resolution();
        }
      }
    }
    bool participating = false;
    bool varying = false;
    for (uint32_t m : instance.materials) {
      const Material& material = scene.materials[m];
      const bool medium =
          material.participating() && (!material.surface || material.transmissive());
      participating |= medium;
      varying |= medium && material.heterogeneous();
    }
    if (varying) {
      objects.heterogeneous += 1;
    } else if (participating) {
      objects.homogeneous += 1;
    }
  }
  return objects;
}

// What light a medium scatters, in the volumes' report line: the lamps always, and the
// emitters and the world where the effects decided on them.
std::string scattered_light(const CompiledScene& scene, const Effects& effects) {
  std::vector<std::string> lights;
  if (!scene.lights.empty()) lights.push_back("the lamps'");
  if (effects.has(kEmitterEffect)) lights.push_back("the emissive meshes'");
  if (effects.has(kWorldLightEffect)) lights.push_back("the world's");
  if (lights.empty()) return "no light (none in the scene)";
  std::string text = lights[0];
  for (size_t i = 1; i < lights.size(); ++i) {
    text += (i + 1 == lights.size() ? " and " : ", ") + lights[i];
  }
  return text + " light";
}

// What the volumes' report line says of glowing media (CompiledScene::glowing): that
// their glow lights surfaces and media (integrator/glow.h), or nothing.
std::string glow_why(size_t glowing) {
  if (glowing == 0) return "";
  return "; the glow of " + thousands(glowing) + (glowing == 1 ? " object" : " objects") +
         " lights surfaces and media (feelers aimed at it)";
}

// The report's reason for the volumes: "1 object: homogeneous, ..." or, with media a
// program drives, how many of each and the march's step rate; "the world" for its volume.
std::string media_why(const MediaObjects& media, bool world, const Settings& settings,
                      const std::string& scattered) {
  const size_t total = media.total();
  std::string why = total > 0 ? thousands(total) + (total == 1 ? " object" : " objects") : "";
  if (world) why += total > 0 ? " and the world" : "the world";
  why += ": ";
  if (media.heterogeneous == 0) return why + "homogeneous, single scattering of " + scattered;
  if (media.homogeneous > 0) why += thousands(media.homogeneous) + " homogeneous, ";
  if (total > 1) why += thousands(media.heterogeneous) + " ";
  why += "heterogeneous";
  if (media.grids > 0) {
    // "(a Volume object's grids, 64^3 voxels)", "(2 of them Volume objects' grids, the
    // largest 64x64x32 voxels)"
    const glm::ivec3& r = media.largest;
    const std::string side =
        r.x == r.y && r.y == r.z
            ? std::to_string(r.x) + "^3"
            : std::to_string(r.x) + "x" + std::to_string(r.y) + "x" + std::to_string(r.z);
    const std::string which =
        media.grids == media.heterogeneous ? "" : thousands(media.grids) + " of them ";
    why +=
        " (" + which +
        (media.grids == 1 ? "a Volume object's grids, " : "Volume objects' grids, the largest ") +
        side + " voxels)";
  }
  char rate[32];
  std::snprintf(rate, sizeof rate, "%g", static_cast<double>(settings.volume_step_rate));
  return why + ", ray marched at step rate " + rate + ", single scattering of " + scattered;
}

// Which of shadows, reflection, refraction and translucency the scene can show.
void analyse_scene(const CompiledScene& scene, const Settings& settings, Effects* effects) {
  // Only materials some instance uses can contribute, and only where some ray sees it.
  std::vector<bool> used(scene.materials.size(), false);
  bool any_blocker = false;
  for (const CompiledScene::Instance& instance : scene.instances) {
    if (instance.visibility == 0) continue;
    for (uint32_t m : instance.materials) used[m] = true;
    if (instance.materials.empty()) used[0] = true;
    any_blocker |= (instance.visibility & kShadowRay) != 0;
  }
  bool reflective = false;
  int glossy = 0;  // used materials whose reflection can be glossy
  bool transmissive = false;
  bool translucent = false;
  for (size_t m = 0; m < scene.materials.size(); ++m) {
    if (!used[m]) continue;
    const Material& mat = scene.materials[m];
    reflective |= mat.reflective() || mat.transmissive();
    glossy += mat.glossy() ? 1 : 0;
    transmissive |= mat.transmissive();
    // Glass lets feelers through only when its shadows are tinted (settings.h).
    translucent |=
        mat.cut_out() || (settings.glass_shadows == GlassShadows::kTinted && mat.transmissive());
  }
  // An emissive mesh's feelers are shadowed, and the world's. Media dim the feelers that
  // cross them whether or not anything blocks them.
  bool casting = !scene.mesh_lights->empty() || scene.world_light != nullptr;
  for (const Light& light : scene.lights) casting |= light.cast_shadows;
  const MediaObjects volumes = media_objects(scene);
  const size_t media = volumes.total();
  const bool world_medium = scene.world_medium.participating();
  const bool any_medium = media > 0 || world_medium;
  decide(effects, kShadowEffect, casting && (any_blocker || any_medium), "shadows",
         !casting      ? "no light casts shadows"
         : any_blocker ? "lights cast shadows"
         : any_medium  ? "lights cast shadows through media"
                       : "nothing is visible to shadow rays");
  const MeshLights& emitters = *scene.mesh_lights;
  const size_t objects = emitters.objects();
  const size_t triangles = emitters.triangles().size();
  decide(effects, kEmitterEffect, !emitters.empty(), "emissive meshes as lights",
         emitters.empty()
             ? "no mesh emits with its Emission Sampling on"
             : std::to_string(objects) + (objects == 1 ? " object, " : " objects, ") +
                   thousands(triangles) + (triangles == 1 ? " triangle" : " triangles"));
  const WorldLightParams& world = scene.world_light_params;
  decide(effects, kWorldLightEffect, scene.world_light != nullptr, "world light",
         scene.world_light != nullptr || !world.on ? world.why : "the world is black");
  // At maximum depth 0 no mirror or refracted ray is traced, unless the Cut Weight pass
  // asks: then the kernel reaches them to count what the depth cuts (and adds nothing).
  const bool cut_weight = (settings.passes & pass_bit(FilmPass::kCutWeight)) != 0;
  const bool no_bounce = settings.max_depth == 0 && !cut_weight;
  decide(effects, kReflectionEffect, reflective && !no_bounce, "reflection",
         no_bounce    ? "maximum depth 0"
         : reflective ? "reflective or transmissive materials"
                      : "no reflective or transmissive material");
  decide(effects, kGlossyEffect, glossy > 0 && !no_bounce, "glossy reflection",
         no_bounce    ? "maximum depth 0"
         : glossy > 0 ? std::to_string(glossy) + (glossy == 1 ? " material" : " materials") +
                            " rough above 0.02"
                      : "no material rougher than a mirror (roughness 0.02)");
  decide(effects, kRefractionEffect, transmissive && !no_bounce, "refraction",
         no_bounce      ? "maximum depth 0"
         : transmissive ? "transmissive materials"
                        : "no transmissive material");
  decide(effects, kTranslucencyEffect, translucent, "translucency",
         translucent ? "materials with alpha, or glass with tinted shadows"
                     : "no material lets shadow feelers through");
  decide(effects, kVolumeEffect, any_medium, "volumes",
         any_medium ? media_why(volumes, world_medium, settings, scattered_light(scene, *effects)) +
                          glow_why(scene.glowing.size())
                    : "no mesh encloses a medium (a material's volume shader) and the world "
                      "has no volume");
  // Shadow catchers the camera can see (catcher.h), and what the film makes of them.
  size_t catchers = 0;
  for (const CompiledScene::Instance& instance : scene.instances) {
    catchers += instance.shadow_catcher && (instance.visibility & kCameraRay) != 0;
  }
  const std::string caught = thousands(catchers) + (catchers == 1 ? " object" : " objects");
  const std::string them = catchers == 1 ? "it" : "them";
  std::string why = "no object is a shadow catcher";
  if (catchers > 0 && (settings.passes & pass_bit(FilmPass::kShadowCatcher)) != 0) {
    why = caught + ": Combined leaves " + them + " out, the Shadow Catcher pass holds the " +
          "shadows cast on " + them;
  } else if (catchers > 0) {
    why = caught + ": camera rays show only the shadows cast on " + them + ", " +
          (settings.transparent_background ? "as alpha over the transparent film"
                                           : "over the world behind " + them);
  }
  decide(effects, kCatcherEffect, catchers > 0, "shadow catcher", why);
  effects->decisions.push_back(strands(scene));
  effects->decisions.push_back(light_linking(scene));
  effects->decisions.push_back(lamps_seen(scene));
  effects->decisions.push_back(lamp_programs(scene));
  effects->decisions.push_back(program_rays(scene));
  effects->decisions.push_back(udim_images(scene));
}

// "0.0250": a length as the report writes it, in scene units.
std::string length_text(float value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", static_cast<double>(value));
  return text;
}

// Whether anything moves within the shutter, and what.
EffectDecision motion_blur(const CompiledScene& scene, const Settings& settings,
                           const Camera& camera) {
  if (!(settings.shutter > 0.0f)) {
    return {"motion blur", false,
            "Render > Motion Blur off, a zero shutter, or the viewport (as in Cycles)"};
  }
  size_t moving = 0;
  size_t deforming = 0;
  for (const CompiledScene::Instance& instance : scene.instances) {
    moving += instance.motion != nullptr;
    deforming += instance.mesh->mesh.deforms();
  }
  const std::string shutter = "shutter " + length_text(settings.shutter) + " frames";
  if (moving == 0 && deforming == 0 && !camera.motion) {
    return {"motion blur", false, "nothing moves within the " + shutter};
  }
  std::vector<std::string> parts;
  if (moving > 0)
    parts.push_back(thousands(moving) + (moving == 1 ? " moving object" : " moving objects"));
  if (deforming > 0) {
    parts.push_back(thousands(deforming) +
                    (deforming == 1 ? " deforming object" : " deforming objects"));
  }
  std::string what;
  for (size_t i = 0; i < parts.size(); ++i) what += (i > 0 ? ", " : "") + parts[i];
  if (camera.motion) what = what.empty() ? "the camera moves" : what + " and the camera";
  return {"motion blur", true, what + ", " + shutter};
}

}  // namespace

Effects analyse(const CompiledScene& scene, const Settings& settings, const Camera& camera) {
  Effects effects;
  if (settings.analysis) {
    analyse_scene(scene, settings, &effects);
    effects.decisions.push_back(
        {"depth of field", camera.lens.blurs(),
         camera.lens.blurs() ? "aperture radius " + length_text(camera.lens.radius) +
                                   ", in focus at " + length_text(camera.lens.focus_distance)
                             : "a pinhole camera (Depth of Field off, or no aperture)"});
    effects.decisions.push_back(motion_blur(scene, settings, camera));
  } else {
    effects.decisions.push_back({"analysis", false, "every effect on"});
  }
  decide(&effects, kPruningEffect, settings.feeler_pruning, "pruning",
         settings.feeler_pruning ? "shadow feelers that cannot show are skipped (cutoff " +
                                       std::to_string(settings.cutoff) + ")"
                                 : "a feeler to every light sample");
  return effects;
}

}  // namespace whitted
