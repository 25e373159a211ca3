// Mesh and scene import through assimp 5.2, with everything assimp hands back validated.
//
// Post-processing: none (flags = 0). aiProcess_Triangulate would split polygons itself, and
// SortByPType, OptimizeMeshes, PreTransformVertices and friends reorder or merge faces; without
// them assimp returns each mesh's faces in file order with polygon indices in file order, and
// we fan-split them here (CONVENTIONS). aiProcess_ValidateDataStructure is not used either: we
// check every field we read ourselves, so a hostile file meets the same checks whatever
// assimp's validation would have caught. docs/scene-format.md ("Triangle order on import")
// records which order holds for each format.
#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/scene.h>
#include <assimp/version.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <string_view>
#include <unordered_map>
#include <unordered_set>

#include "rtt/error.h"
#include "scene/affine.h"
#include "scene/importers.h"
#include "scene/texture_colour.h"

namespace rtt::detail {
namespace {

constexpr size_t max_node_depth = 1024;
constexpr double rad_to_deg = 180.0 / 3.14159265358979323846;

Vec3f vec(const aiVector3D& v) {
    return {v.x, v.y, v.z};
}

Affine to_affine(const aiMatrix4x4& a) {
    // assimp matrices are row-major with the translation in the 4th column; like assimp's own
    // aiMatrix4x4 * aiVector3D we ignore the (projective) last row.
    Affine r;
    const float* row[3] = {&a.a1, &a.b1, &a.c1};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) r.m[i][j] = row[i][j];
    return r;
}

/// Shading models whose materials have no specular lobe: assimp reports e.g. OBJ "illum 1" and
/// COLLADA <lambert> this way while still filling in a specular colour.
bool has_specular(int shading_model) {
    switch (shading_model) {
        case aiShadingMode_Flat:
        case aiShadingMode_Gouraud:
        case aiShadingMode_OrenNayar:
        case aiShadingMode_Minnaert:
        case aiShadingMode_NoShading:
            return false;
        default:
            return true;
    }
}

Material convert_material(const aiMaterial& m) {
    Material out;
    aiString name;
    if (m.Get(AI_MATKEY_NAME, name) == AI_SUCCESS && name.length > 0)
        out.name = one_line(name.C_Str());
    // Importers invent "DefaultMaterial" when the file has none: that is our default grey.
    if (out.name == AI_DEFAULT_MATERIAL_NAME) return Material{};
    aiColor3D c;
    if (m.Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS) out.diffuse = {c.r, c.g, c.b};
    if (m.Get(AI_MATKEY_COLOR_SPECULAR, c) == AI_SUCCESS) out.specular = {c.r, c.g, c.b};
    float f = 0.f;
    if (m.Get(AI_MATKEY_SHININESS, f) == AI_SUCCESS) out.shininess = f;
    if (m.Get(AI_MATKEY_REFLECTIVITY, f) == AI_SUCCESS) out.mirror = f;
    int shading = 0;
    if (m.Get(AI_MATKEY_SHADING_MODEL, shading) == AI_SUCCESS && !has_specular(shading))
        out.specular = Vec3f{0.f};
    // Out-of-range values are clamped (NaN stays NaN, and validate() rejects it).
    out.diffuse = min(max(out.diffuse, Vec3f{0.f}), Vec3f{1.f});
    out.specular = min(max(out.specular, Vec3f{0.f}), Vec3f{1.f});
    out.shininess = std::max(out.shininess, 0.f);
    out.mirror = std::clamp(out.mirror, 0.f, 1.f);
    return out;
}

class AssimpImport {
public:
    AssimpImport(const std::string& path, const aiScene& ai)
        : path_(path),
          ai_(ai),
          ext_(lower_extension(path)),
          gltf_(ext_ == "gltf" || ext_ == "glb"),
          // These formats have no material model: what assimp reports is invented.
          ignore_materials_(ext_ == "stl" || ext_ == "ply" || ext_ == "off"),
          mesh_tris_(ai.mNumMeshes),
          mesh_checked_(ai.mNumMeshes, false),
          material_map_(ai.mNumMaterials, invalid_triangle),
          colour_materials_(ai.mNumMeshes) {
        scene_.name = path;
    }

    Scene run() {
        if (!ai_.mRootNode) fail("the file has no scene graph");
        walk_nodes();
        if (scene_.triangles.empty()) {
            std::string why = ai_.mNumMeshes == 0 ? "the file has no meshes" : "";
            if (skipped_points_ + skipped_lines_ > 0)
                why = "skipped " + std::to_string(skipped_points_) + " points and " +
                      std::to_string(skipped_lines_) + " lines";
            fail(why.empty() ? "no triangles" : "no triangles (" + why + ")");
        }
        for (unsigned i = 0; i < ai_.mNumCameras && ai_.mCameras; ++i)
            import_camera(ai_.mCameras[i]);
        if (!scene_.file_cameras.empty()) scene_.camera = scene_.file_cameras.front().camera;
        for (unsigned i = 0; i < ai_.mNumLights && ai_.mLights; ++i) import_light(ai_.mLights[i]);
        return std::move(scene_);
    }

private:
    [[noreturn]] void fail(const std::string& message) const { throw Error(path_, 0, message); }

    std::string mesh_label(unsigned index) const {
        const aiMesh* m = ai_.mMeshes[index];
        std::string label = "mesh " + std::to_string(index);
        if (m && m->mName.length > 0) label += " \"" + one_line(m->mName.C_Str()) + "\"";
        return label;
    }

    /// Depth-first pre-order: a node's meshes in its mMeshes order, then its children in order.
    void walk_nodes() {
        struct Item {
            const aiNode* node;
            Affine parent;
            size_t depth;
        };
        std::vector<Item> stack{{ai_.mRootNode, Affine{}, 0}};
        std::unordered_set<const aiNode*> seen;
        while (!stack.empty()) {
            const Item item = stack.back();
            stack.pop_back();
            const aiNode& node = *item.node;
            if (item.depth > max_node_depth)
                fail("node hierarchy deeper than " + std::to_string(max_node_depth) + " levels");
            if (!seen.insert(&node).second) fail("the node graph has a cycle");
            const Affine xf = item.parent * to_affine(node.mTransformation);
            node_transform_.try_emplace(node.mName.C_Str(), xf);
            if (node.mNumMeshes > 0 && !node.mMeshes) fail("a node lists meshes but has none");
            for (unsigned k = 0; k < node.mNumMeshes; ++k) {
                const unsigned index = node.mMeshes[k];
                if (index >= ai_.mNumMeshes || !ai_.mMeshes || !ai_.mMeshes[index])
                    fail("node \"" + one_line(node.mName.C_Str()) + "\" references missing mesh " +
                         std::to_string(index));
                add_instance(index, xf);
            }
            if (node.mNumChildren > 0 && !node.mChildren)
                fail("a node lists children but has none");
            for (unsigned k = node.mNumChildren; k-- > 0;)
                if (node.mChildren[k]) stack.push_back({node.mChildren[k], xf, item.depth + 1});
        }
    }

    /// The mesh's triangles after fan splitting, checked once per mesh however often it is
    /// instanced.
    const std::vector<TriangleIndices>& triangles_of(unsigned index) {
        if (mesh_checked_[index]) return mesh_tris_[index];
        const aiMesh& m = *ai_.mMeshes[index];
        std::vector<TriangleIndices>& tris = mesh_tris_[index];
        mesh_checked_[index] = true;
        if (m.mNumVertices == 0 || !m.mVertices) {
            // An empty part (an STL "solid" without facets) draws nothing: skipped.
            scene_.warn(path_ + ": " + mesh_label(index) + ": no vertices, skipped");
            return tris;
        }
        if (m.mNumFaces > 0 && !m.mFaces) fail(mesh_label(index) + ": faces missing");
        for (unsigned f = 0; f < m.mNumFaces; ++f) {
            const aiFace& face = m.mFaces[f];
            if (face.mNumIndices == 0 || !face.mIndices)
                fail(mesh_label(index) + ": face " + std::to_string(f) +
                     " has no vertex indices (truncated file?)");
            for (unsigned k = 0; k < face.mNumIndices; ++k)
                if (face.mIndices[k] >= m.mNumVertices)
                    fail(mesh_label(index) + ": face " + std::to_string(f) + " uses vertex " +
                         std::to_string(face.mIndices[k]) + " but the mesh has " +
                         std::to_string(m.mNumVertices) + " vertices");
            if (face.mNumIndices == 1)
                ++skipped_points_;
            else if (face.mNumIndices == 2)
                ++skipped_lines_;
            else
                append_fan(face.mIndices, face.mNumIndices, tris);
        }
        return tris;
    }

    uint32_t material_of(const aiMesh& m) {
        if (ignore_materials_ || ai_.mNumMaterials == 0) return default_material();
        if (m.mMaterialIndex >= ai_.mNumMaterials || !ai_.mMaterials ||
            !ai_.mMaterials[m.mMaterialIndex])
            fail("a mesh uses missing material " + std::to_string(m.mMaterialIndex));
        uint32_t& mapped = material_map_[m.mMaterialIndex];
        if (mapped == invalid_triangle) {
            const aiMaterial& am = *ai_.mMaterials[m.mMaterialIndex];
            Material out = convert_material(am);
            if (out.name != AI_DEFAULT_MATERIAL_NAME) apply_texture(am, out);
            mapped = scene_.add_material(out);
        }
        return mapped;
    }

    /// A base-colour (glTF) or diffuse texture counts as its mean colour, times the material's
    /// own colour when the file gives one (texture_colour.h). One that cannot be read leaves
    /// the colour as it is, with a warning.
    void apply_texture(const aiMaterial& am, Material& out) {
        for (const aiTextureType type : {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE}) {
            aiString file;
            if (am.GetTextureCount(type) == 0 || am.GetTexture(type, 0, &file) != AI_SUCCESS)
                continue;
            std::optional<Vec3f> mean;
            if (const aiTexture* t = ai_.GetEmbeddedTexture(file.C_Str())) {
                if (t->mHeight == 0 && t->pcData)  // an image file's bytes, mWidth of them
                    mean = mean_encoded_colour(
                        std::span(reinterpret_cast<const uint8_t*>(t->pcData), size_t(t->mWidth)));
                else if (t->pcData)
                    mean = mean_of_texels(*t);
            } else if (file.length > 0) {
                mean = mean_image_colour(
                    (std::filesystem::path(path_).parent_path() / file.C_Str()).string());
            }
            aiColor3D c;
            const bool coloured = am.Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS;
            if (mean)
                out.diffuse = (coloured ? out.diffuse : Vec3f{1.f}) * *mean;
            else
                scene_.warn(path_ + ": texture \"" + one_line(file.C_Str()) + "\" of material \"" +
                            out.name + "\" cannot be read; the material keeps its colour");
            return;
        }
    }

    static Vec3f mean_of_texels(const aiTexture& t) {
        const size_t n = size_t(t.mWidth) * size_t(t.mHeight);
        std::vector<uint8_t> rgba(4 * n);
        for (size_t i = 0; i < n; ++i) {
            rgba[4 * i] = t.pcData[i].r;
            rgba[4 * i + 1] = t.pcData[i].g;
            rgba[4 * i + 2] = t.pcData[i].b;
            rgba[4 * i + 3] = t.pcData[i].a;
        }
        return mean_texel_colour(rgba.data(), n);
    }

    /// Per triangle of mesh `index`, the material for its vertex colours (the mean of its three
    /// vertices' first colour set, times the mesh material's colour), or none when the mesh has
    /// no vertex colours. Materials are shared by triangles whose colours agree in 8 bits.
    const std::vector<uint32_t>& vertex_colour_materials(unsigned index, uint32_t base) {
        std::vector<uint32_t>& out = colour_materials_[index];
        const aiMesh& m = *ai_.mMeshes[index];
        if (!out.empty() || !m.mColors[0]) return out;
        const std::vector<TriangleIndices>& tris = mesh_tris_[index];
        out.resize(tris.size());
        for (size_t t = 0; t < tris.size(); ++t) {
            Vec3f sum{0.f};
            for (const uint32_t v : tris[t]) {
                const aiColor4D& c = m.mColors[0][v];
                sum = sum + Vec3f{c.r, c.g, c.b};
            }
            const Vec3f mean = min(max(sum / 3.f, Vec3f{0.f}), Vec3f{1.f});
            // NaN colours (a broken file) keep the mesh's material.
            if (!is_finite(mean)) {
                out[t] = base;
                continue;
            }
            const uint32_t key = uint32_t(std::lround(mean.x * 255.f)) |
                                 uint32_t(std::lround(mean.y * 255.f)) << 8 |
                                 uint32_t(std::lround(mean.z * 255.f)) << 16;
            const auto [it, added] = colour_keys_.try_emplace({base, key}, 0u);
            if (added) {
                Material mat = scene_.materials[base];
                mat.diffuse = mat.diffuse * mean;
                it->second = scene_.add_material(mat);
            }
            out[t] = it->second;
        }
        return out;
    }

    uint32_t default_material() {
        if (default_material_ == invalid_triangle) default_material_ = scene_.add_material({});
        return default_material_;
    }

    void add_instance(unsigned index, const Affine& xf) {
        const std::vector<TriangleIndices>& tris = triangles_of(index);
        if (tris.empty()) return;
        const aiMesh& m = *ai_.mMeshes[index];
        constexpr size_t limit = std::numeric_limits<uint32_t>::max() - 1;
        if (scene_.vertices.size() + m.mNumVertices > limit ||
            scene_.triangles.size() + tris.size() > limit)
            fail("more than 2^32 - 2 vertices or triangles (meshes instanced too often?)");
        if (!xf.is_finite()) fail("a node transform has a NaN or infinite entry");
        const bool identity = xf.is_identity();
        std::vector<Vec3f> verts(m.mNumVertices), normals;
        for (unsigned v = 0; v < m.mNumVertices; ++v) {
            // The identity case copies, so untransformed files keep their exact bits. NaN or
            // infinite vertices are dealt with by load_mesh_file (drop_non_finite_triangles).
            verts[v] = identity ? vec(m.mVertices[v]) : xf.point(vec(m.mVertices[v]));
            if (!is_finite(verts[v]) && is_finite(vec(m.mVertices[v])))
                fail(mesh_label(index) + ": vertex " + std::to_string(v) +
                     " is not finite after the node transform");
        }
        if (m.mNormals) {
            normals.resize(m.mNumVertices);
            for (unsigned v = 0; v < m.mNumVertices; ++v) {
                const Vec3f n = vec(m.mNormals[v]);
                // A broken normal falls back to the geometric normal (the zero vector).
                normals[v] = !is_finite(n) ? Vec3f{0.f} : identity ? n : xf.normal(n);
            }
        }
        const uint32_t material = material_of(m);
        const size_t first = scene_.triangles.size();
        scene_.add_mesh(verts, tris, material, normals);
        const std::vector<uint32_t>& colours = vertex_colour_materials(index, material);
        for (size_t t = 0; t < colours.size(); ++t)
            scene_.triangle_material[first + t] = colours[t];
    }

    Affine transform_of(const aiString& name) const {
        const auto it = node_transform_.find(name.C_Str());
        return it == node_transform_.end() ? Affine{} : it->second;
    }

    /// A perspective camera, appended to the scene's file cameras. assimp's mHorizontalFOV is, in
    /// practice, the FULL horizontal angle for COLLADA and glTF (assimp issue #2256, despite
    /// camera.h saying half); assimp <= 5.2 builds it for glTF as yfov * aspect (issue #4435, fixed
    /// in 5.3 to 2 atan(tan(yfov/2) aspect)), and sets a glTF camera's mPosition to its node's
    /// translation although the node transform already holds it (issue #5054), so for glTF the
    /// camera sits at its node's origin.
    void import_camera(const aiCamera* cam) {
        if (!cam || cam->mOrthographicWidth > 0.f || cam->mHorizontalFOV == 0.f)
            return;  // orthographic
        const std::string label = "camera \"" + one_line(cam->mName.C_Str()) + "\"";
        const Affine xf = transform_of(cam->mName);
        const double hfov = cam->mHorizontalFOV;
        const double aspect = cam->mAspect > 0.f ? cam->mAspect : 1.0;
        const bool linear_gltf_fov =
            gltf_ &&
            (aiGetVersionMajor() < 5 || (aiGetVersionMajor() == 5 && aiGetVersionMinor() <= 2));
        const double fovy =
            linear_gltf_fov ? hfov / aspect : 2.0 * std::atan(std::tan(hfov / 2.0) / aspect);
        Camera c;
        c.position = xf.point(gltf_ ? Vec3f{0.f} : vec(cam->mPosition));
        const Vec3f dir = xf.vector(vec(cam->mLookAt));
        c.up = xf.vector(vec(cam->mUp));
        c.fovy_deg = float(fovy * rad_to_deg);
        if (!is_finite(c.position) || !is_finite(dir) || !is_finite(c.up) || !std::isfinite(hfov))
            fail(label + ": NaN or infinite value");
        if (!(c.fovy_deg > 0.f && c.fovy_deg < 180.f) || !(hfov > 0.0))
            fail(label + ": field of view out of range");
        if (length(dir) == 0.f || length(cross(dir, c.up)) == 0.f)
            fail(label + ": view direction is zero or parallel to the up vector");
        // A target at a distance comparable to the position keeps the direction's precision.
        c.target = c.position + normalize(dir) * std::max(1.f, length(c.position));
        scene_.file_cameras.push_back(FileCamera{one_line(cam->mName.C_Str()), c});
    }

    /// Point lights become omni, spot lights spot; other kinds are skipped. assimp's colour is
    /// colour x intensity: we split it as intensity = largest component. Cone angles are full
    /// angles except for glTF, whose importer copies KHR_lights_punctual's half angles.
    void import_light(const aiLight* l) {
        if (!l || (l->mType != aiLightSource_POINT && l->mType != aiLightSource_SPOT)) return;
        const std::string label = "light \"" + one_line(l->mName.C_Str()) + "\"";
        const Affine xf = transform_of(l->mName);
        Light out;
        out.kind = l->mType == aiLightSource_SPOT ? LightKind::spot : LightKind::omni;
        out.position = xf.point(vec(l->mPosition));
        const Vec3f c =
            max(Vec3f{l->mColorDiffuse.r, l->mColorDiffuse.g, l->mColorDiffuse.b}, Vec3f{0.f});
        out.intensity = std::max({c.x, c.y, c.z});
        out.color = out.intensity > 0.f ? c / out.intensity : Vec3f{1.f};
        if (out.kind == LightKind::spot) {
            out.direction = xf.vector(vec(l->mDirection));
            const double half = gltf_ ? 1.0 : 0.5;
            const auto angle = [&](float a) {
                return float(std::clamp(a * half * rad_to_deg, 0.0, 180.0));
            };
            out.outer_angle_deg = angle(l->mAngleOuterCone);
            out.inner_angle_deg = std::min(angle(l->mAngleInnerCone), out.outer_angle_deg);
            if (is_finite(out.direction) && length(out.direction) == 0.f)
                fail(label + ": spot light without a direction");
        }
        if (!is_finite(out.position) || !is_finite(out.direction) || !is_finite(out.color) ||
            !std::isfinite(out.intensity) || std::isnan(out.inner_angle_deg) ||
            std::isnan(out.outer_angle_deg))
            fail(label + ": NaN or infinite value");
        scene_.lights.push_back(out);
    }

    const std::string& path_;
    const aiScene& ai_;
    const std::string ext_;
    const bool gltf_, ignore_materials_;
    Scene scene_;
    std::vector<std::vector<TriangleIndices>> mesh_tris_;
    std::vector<bool> mesh_checked_;
    std::vector<uint32_t> material_map_;
    std::vector<std::vector<uint32_t>> colour_materials_;  ///< Per mesh: vertex_colour_materials.
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> colour_keys_;  ///< (base, rgb8) -> material.
    uint32_t default_material_ = invalid_triangle;
    std::unordered_map<std::string, Affine> node_transform_;
    size_t skipped_points_ = 0, skipped_lines_ = 0;
};

}  // namespace

Scene import_assimp(const std::string& path) {
    PlyCheck ply;
    {
        // assimp reads a file as PLY by its extension or by a leading "ply", whatever follows.
        std::ifstream in(path, std::ios::binary);
        char magic[3] = {};
        in.read(magic, 3);
        if (lower_extension(path) == "ply" || std::string_view(magic, 3) == "ply")
            ply = check_ply_structure(path);
    }
    // No DefaultLogger is created, so assimp logs nothing to stdout or stderr.
    Assimp::Importer importer;
    // Some importers (BVH, MD5, ...) invent a mesh that draws the skeleton when a file has no
    // geometry; we want "no triangles" instead.
    importer.SetPropertyBool(AI_CONFIG_IMPORT_NO_SKELETON_MESHES, true);
    const aiScene* ai = nullptr;
    try {
        // A repaired PLY is read from memory (a PLY refers to no other file).
        ai = ply.repaired.empty()
                 ? importer.ReadFile(path, 0)
                 : importer.ReadFileFromMemory(ply.repaired.data(), ply.repaired.size(), 0, "ply");
    } catch (const std::exception& e) {
        // ReadFile turns exceptions into GetErrorString() only when assimp was built with
        // ASSIMP_CATCH_GLOBAL_EXCEPTIONS (Debian's is); other builds let std::bad_alloc escape.
        throw Error(path, 0, one_line(e.what()));
    }
    if (!ai) {
        std::string why = one_line(importer.GetErrorString());
        if (why.empty()) why = "assimp could not read the file";
        // assimp turns exceptions into messages; this one means the sandbox's memory limit.
        if (why == "std::bad_alloc")
            why = "the importer (assimp) ran out of memory on this file (malformed, or too large)";
        // A repair that may be why (a misspelt PLY keyword read as a comment).
        if (!ply.warnings.empty()) why += " (after a repair: " + ply.warnings.front() + ")";
        throw Error(path, 0, why);
    }
    Scene scene = AssimpImport(path, *ai).run();
    for (std::string& w : ply.warnings) scene.warn(std::move(w));
    return scene;
}

}  // namespace rtt::detail
