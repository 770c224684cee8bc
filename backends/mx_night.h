// mx_night.h: the night preview (analysis/night_render.h: the same diamond sign, sphere,
// camera and lights) of any MaterialX material, shaded by the GLSL real MaterialX generates for
// it (mx_material.h) on OpenGL (EGL; llvmpipe where there is no GPU).
//
// The sign and the sphere are drawn as meshes: the diamond as two triangles, with texture
// coordinates over its bounding square (u along the sign's horizontal axis, v up: an image
// covers the sign upright, its corners outside the diamond); the sphere as 512 x 256
// longitude-latitude quads (u = longitude / 2 pi: 0 at -z, 0.5 facing the camera at +z,
// growing towards +x; v = latitude, 0 at the
// bottom), normals and tangents analytic at the vertices. Each of the spp x spp sub-pixel
// samples of the reference renderer is a pixel of a render target spp times larger, box-filtered
// down. Each light is drawn alone as MaterialX's point light with decay_rate 0 (MaterialX
// attenuates by (d + 1)^decay_rate) and intensity 1; per sample the result is scaled by the
// scene's I / d^2, and set to 0 where the light is behind the surface or shadowed (the
// reference renderer's rules, from the sample's world position).
//
// Layers: where every rp_prismatic_retroreflector_bsdf node of the material has its specular,
// retro_color and diffuse_color inputs as uniforms (not connected), the material is drawn
// once with each lobe of every such node alone (the other two at 0) and, when the material
// has other nodes, once with all three at 0 (the rest: the graph's other BSDFs, the layer
// `other`). A MaterialX surface is linear in each BSDF's response (layer: top + base x the
// top's throughput; mix: a weighted sum), so a lobe's draw less the rest is the node's lobe as
// it reaches the surface through the graph (under a coat, weighted by a mix): the layers
// surface, retro and diffuse, which with `other` sum to the material's response. Otherwise the
// material is drawn once, into `other`.
#pragma once

#include "mx_material.h"
#include "night_render.h"

namespace retroprism::gl {

// Compiles the material's shaders once (~30 s on llvmpipe for the node's shader) and renders
// the scene with them as often as asked.
class MxNightRenderer {
  public:
    explicit MxNightRenderer(const MxMaterial& material);
    ~MxNightRenderer();
    MxNightRenderer(const MxNightRenderer&) = delete;
    MxNightRenderer& operator=(const MxNightRenderer&) = delete;

    // Whether the node's lobes can be separated (see the header).
    bool lobes() const { return !lobeUniforms_.empty(); }
    // InputError when width x spp or height x spp exceeds the OpenGL implementation's largest
    // render target.
    NightImage render(const NightSettings& settings);

  private:
    void draw_pass(int lobe, int w, int h);
    EglContext context_;
    MxMaterial material_;
    std::vector<std::string> lobeUniforms_; // per rp node: specular, retro_color, diffuse_color
    unsigned program_ = 0, idProgram_ = 0;
    unsigned vao_ = 0, vbo_ = 0, fbo_ = 0, colorTex_ = 0, depthRb_ = 0, envTex_ = 0;
    std::vector<unsigned> textures_;
    int signVertices_ = 0, sphereVertices_ = 0;
};

// The settings' NightImage of the material: compiles, renders once.
NightImage render_night_mx(const MxMaterial& material, const NightSettings& settings);

} // namespace retroprism::gl
