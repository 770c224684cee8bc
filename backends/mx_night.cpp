#include "mx_night.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <regex>

#include "color.h"
#include "error.h"
#include "mtlx_reader.h"
#include "night_scene.h"
#include "parallel.h"

namespace retroprism::gl {

namespace {

using glm::dvec3;

constexpr int kLongitudes = 512, kLatitudes = 256;
constexpr double kNear = 0.1, kFar = 100.0;
// A vertex: position, normal, tangent, bitangent (n x t), texcoord.
constexpr int kFloats = 14;

void push_vertex(std::vector<float>& v, const dvec3& p, const dvec3& n, const dvec3& t, double s,
                 double u) {
    const dvec3 b = glm::cross(n, t);
    for (const dvec3& x : {p, n, t, b})
        v.insert(v.end(), {float(x.x), float(x.y), float(x.z)});
    v.insert(v.end(), {float(s), float(u)});
}

std::vector<float> sign_mesh(const NightSign& sg) {
    const double h = sg.halfDiagonal;
    const dvec3 corner[4] = {sg.c + h * sg.u, sg.c + h * sg.v, sg.c - h * sg.u, sg.c - h * sg.v};
    const double uv[4][2] = {{1, 0.5}, {0.5, 1}, {0, 0.5}, {0.5, 0}};
    std::vector<float> v;
    for (int k : {0, 1, 2, 0, 2, 3})
        push_vertex(v, corner[k], sg.n, sg.u, uv[k][0], uv[k][1]);
    return v;
}

void sphere_vertex(std::vector<float>& v, const NightSphere& sp, int i, int j) {
    const double theta = -M_PI / 2 + M_PI * i / kLatitudes;
    const double phi = -M_PI + 2 * M_PI * j / kLongitudes;
    const dvec3 n(std::cos(theta) * std::sin(phi), std::sin(theta),
                  std::cos(theta) * std::cos(phi));
    push_vertex(v, sp.c + sp.r * n, n, dvec3(std::cos(phi), 0.0, -std::sin(phi)),
                double(j) / kLongitudes, double(i) / kLatitudes);
}

std::vector<float> sphere_mesh(const NightSphere& sp) {
    std::vector<float> v;
    for (int i = 0; i < kLatitudes; ++i)
        for (int j = 0; j < kLongitudes; ++j)
            for (const auto& c : {std::make_pair(0, 0), std::make_pair(1, 0), std::make_pair(1, 1),
                                  std::make_pair(0, 0), std::make_pair(1, 1), std::make_pair(0, 1)})
                sphere_vertex(v, sp, i + c.first, j + c.second);
    return v;
}

// The fragment stage of the geometry pass: the world position and the object (1 sign,
// 2 sphere), reading the interface block MaterialX's vertex stage writes.
std::string id_fragment(const std::string& fragment) {
    std::smatch m;
    if (!std::regex_search(fragment, m, std::regex(R"(in VertexData\s*\{[^}]*\}\s*vd;)")) ||
        m.str().find("positionWorld") == std::string::npos)
        throw GlError("MaterialX's fragment shader has no VertexData block with positionWorld");
    return "#version 400\n" + m.str() +
           "\nuniform int u_objectId;\nout vec4 out1;\n"
           "void main() { out1 = vec4(vd.positionWorld, float(u_objectId + 1)); }\n";
}

Mat4 projection(const NightScene& s) {
    const float a = float((kFar + kNear) / (kNear - kFar));
    const float b = float(2 * kFar * kNear / (kNear - kFar));
    return {float(1 / s.tanX), 0, 0, 0, 0, float(1 / s.tanY), 0, 0, 0, 0, a, -1, 0, 0, b, 0};
}

void set_values(unsigned program, const std::string& variable, const std::vector<double>& v) {
    const GLint loc = glGetUniformLocation(program, variable.c_str());
    if (loc < 0) return;
    if (v.size() == 1) glUniform1f(loc, float(v[0]));
    if (v.size() == 2) glUniform2f(loc, float(v[0]), float(v[1]));
    if (v.size() == 3) glUniform3f(loc, float(v[0]), float(v[1]), float(v[2]));
    if (v.size() == 4) glUniform4f(loc, float(v[0]), float(v[1]), float(v[2]), float(v[3]));
}

// A colour or float uniform's value in the working space: colours written in another colour
// space converted with OpenColorIO (MaterialX's colour management, which its JavaScript build
// leaves out).
std::vector<double> working_value(const MxUniform& u) {
    std::vector<double> v = mx_values(u);
    if ((u.type == "color3" || u.type == "color4") && !u.colorspace.empty() &&
        u.colorspace != kMtlxWorkingSpace) {
        const Color3 lin = to_lin_rec709(u.colorspace, {v[0], v[1], v[2]});
        std::copy(lin.begin(), lin.end(), v.begin());
    }
    return v;
}

int uniform_int(const MxMaterial& m, const std::string& path, int fallback) {
    const MxUniform* u = m.find(path);
    return u && !u->value.empty() ? int(mx_values(*u).at(0)) : fallback;
}

// MaterialX's address modes (constant, clamp, periodic, mirror) as OpenGL wrap modes.
GLint wrap_mode(int mode) {
    const GLint modes[4] = {GL_CLAMP_TO_BORDER, GL_CLAMP_TO_EDGE, GL_REPEAT, GL_MIRRORED_REPEAT};
    return modes[std::clamp(mode, 0, 3)];
}

// Uploads a texture to `unit` with the image node's address modes, filter and default colour.
unsigned upload_texture(const MxMaterial& m, const MxTexture& t, int unit) {
    unsigned tex = 0;
    glGenTextures(1, &tex);
    glActiveTexture(GLenum(GL_TEXTURE0 + unit));
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, t.width, t.height, 0, GL_RGBA, GL_FLOAT,
                 t.rgba.data());
    glGenerateMipmap(GL_TEXTURE_2D);
    const bool closest = uniform_int(m, t.node + "/filtertype", 1) == 0;
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER,
                    closest ? GL_NEAREST_MIPMAP_NEAREST : GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, closest ? GL_NEAREST : GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S,
                    wrap_mode(uniform_int(m, t.node + "/uaddressmode", 2)));
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T,
                    wrap_mode(uniform_int(m, t.node + "/vaddressmode", 2)));
    float border[4] = {0, 0, 0, 1};
    if (const MxUniform* d = m.find(t.node + "/default")) {
        const std::vector<double> v = working_value(*d);
        for (size_t c = 0; c < 4; ++c)
            border[c] = c < v.size() ? float(v[c]) : v.size() == 1 && c < 3 ? float(v[0]) : 1.0f;
    }
    glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, border);
    glActiveTexture(GL_TEXTURE0);
    return tex;
}

// The lobe inputs (specular, retro_color, diffuse_color) of every node of the material, when
// all are uniforms the shader uses; empty otherwise (the lobes cannot be drawn alone).
std::vector<std::string> lobe_uniforms(const MxMaterial& m, unsigned program) {
    std::vector<std::string> nodes, out;
    for (const MxUniform& u : m.uniforms)
        if (u.category == kMtlxNodeCategory &&
            std::find(nodes.begin(), nodes.end(), u.node) == nodes.end())
            nodes.push_back(u.node);
    for (const std::string& n : nodes)
        for (const char* input : {"specular", "retro_color", "diffuse_color"}) {
            const MxUniform* u = m.find(n + "/" + input);
            if (!u || glGetUniformLocation(program, u->variable.c_str()) < 0) return {};
            out.push_back(u->path);
        }
    return out;
}

bool chain_only(const MxMaterial& m) {
    for (const std::string& c : m.categories)
        if (c != "surfacematerial" && c != "surface" && c != kMtlxNodeCategory) return false;
    return true;
}

} // namespace

MxNightRenderer::MxNightRenderer(const MxMaterial& material) : material_(material) {
    const std::vector<MxTexture> textures = load_mx_textures(material_);
    program_ = build_program({{GL_VERTEX_SHADER, material_.shaders.vertex},
                              {GL_FRAGMENT_SHADER, material_.shaders.fragment}});
    idProgram_ = build_program({{GL_VERTEX_SHADER, material_.shaders.vertex},
                                {GL_FRAGMENT_SHADER, id_fragment(material_.shaders.fragment)}});
    glGenVertexArrays(1, &vao_);
    glGenBuffers(1, &vbo_);
    glGenFramebuffers(1, &fbo_);
    glGenTextures(1, &colorTex_);
    glGenRenderbuffers(1, &depthRb_);
    glGenTextures(1, &envTex_);
    glUseProgram(program_);
    // The environment samplers read a black texture on unit 1, and the environment is off.
    const float black[4] = {0, 0, 0, 0};
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, envTex_);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, 1, 1, 0, GL_RGBA, GL_FLOAT, black);
    glActiveTexture(GL_TEXTURE0);
    for (const char* name : {"u_envRadiance", "u_envIrradiance"})
        glUniform1i(glGetUniformLocation(program_, name), 1);
    glUniform1f(glGetUniformLocation(program_, "u_envLightIntensity"), 0.0f);
    for (size_t k = 0; k < textures.size(); ++k) {
        textures_.push_back(upload_texture(material_, textures[k], int(k) + 2));
        glUniform1i(glGetUniformLocation(program_, textures[k].variable.c_str()), int(k) + 2);
    }
    for (const MxUniform& u : material_.uniforms)
        if ((u.type == "color3" || u.type == "color4") && !u.value.empty())
            set_values(program_, u.variable, working_value(u));
    lobeUniforms_ = lobe_uniforms(material_, program_);
}

MxNightRenderer::~MxNightRenderer() {
    context_.use();
    glDeleteTextures(GLsizei(textures_.size()), textures_.data());
    glDeleteTextures(1, &envTex_);
    glDeleteRenderbuffers(1, &depthRb_);
    glDeleteTextures(1, &colorTex_);
    glDeleteFramebuffers(1, &fbo_);
    glDeleteBuffers(1, &vbo_);
    glDeleteVertexArrays(1, &vao_);
    glDeleteProgram(idProgram_);
    glDeleteProgram(program_);
}

namespace {

// Points the vertex stage's attributes (those it declares) at the interleaved vertices.
void bind_attributes(unsigned program, unsigned vao, unsigned vbo) {
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    const struct {
        const char* name;
        int offset, size;
    } attributes[] = {{"i_position", 0, 3},
                      {"i_normal", 3, 3},
                      {"i_tangent", 6, 3},
                      {"i_bitangent", 9, 3},
                      {"i_texcoord_0", 12, 2}};
    for (GLuint a = 0; a < 16; ++a)
        glDisableVertexAttribArray(a);
    for (const auto& a : attributes) {
        const GLint loc = glGetAttribLocation(program, a.name);
        if (loc < 0) continue;
        glEnableVertexAttribArray(GLuint(loc));
        glVertexAttribPointer(GLuint(loc), a.size, GL_FLOAT, GL_FALSE, kFloats * sizeof(float),
                              reinterpret_cast<const void*>(size_t(a.offset) * sizeof(float)));
    }
}

// An RGBA32F colour texture and a depth buffer of w x h as the draw target, cleared.
void make_target(unsigned fbo, unsigned tex, unsigned depth, int w, int h) {
    GLint maxSize = 0, maxViewport[2] = {0, 0};
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, maxViewport);
    const int limit = std::min({maxSize, maxViewport[0], maxViewport[1]});
    if (w > limit || h > limit)
        throw InputError("render: width x samples and height x samples must be at most " +
                         std::to_string(limit) + " (this OpenGL's largest render target); got " +
                         std::to_string(w) + " x " + std::to_string(h));
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, w, h, 0, GL_RGBA, GL_FLOAT, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, w, h);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw GlError("OpenGL: the RGBA32F render target with depth is incomplete");
    glViewport(0, 0, w, h);
    glEnable(GL_DEPTH_TEST);
}

std::vector<float> read_target(int w, int h) {
    std::vector<float> px(size_t(w) * size_t(h) * 4);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_FLOAT, px.data());
    return px;
}

} // namespace

// Draws the scene with lobe k of every node alone (0 surface, 1 retro, 2 diffuse), with all
// three off (3), or as the document says (-1).
void MxNightRenderer::draw_pass(int lobe, int w, int h) {
    for (size_t i = 0; i < lobeUniforms_.size(); ++i) {
        const MxUniform& u = *material_.find(lobeUniforms_[i]);
        std::vector<double> v = working_value(u);
        if (lobe >= 0 && int(i % 3) != lobe) std::fill(v.begin(), v.end(), 0.0);
        set_values(program_, u.variable, v);
    }
    glViewport(0, 0, w, h);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLES, 0, signVertices_ + sphereVertices_);
}

NightImage MxNightRenderer::render(const NightSettings& st) {
    context_.use();
    const NightScene scene = build_night_scene(st);
    const int spp = st.spp, W = st.width * spp, H = st.height * spp;
    make_target(fbo_, colorTex_, depthRb_, W, H);
    std::vector<float> mesh = sign_mesh(scene.sign);
    signVertices_ = int(mesh.size() / kFloats);
    const std::vector<float> sphere = sphere_mesh(scene.sphere);
    sphereVertices_ = int(sphere.size() / kFloats);
    mesh.insert(mesh.end(), sphere.begin(), sphere.end());
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(mesh.size() * sizeof(float)), mesh.data(),
                 GL_STATIC_DRAW);
    const Mat4 vp = projection(scene);

    // The geometry pass: each sample's world position and object.
    glUseProgram(idProgram_);
    bind_attributes(idProgram_, vao_, vbo_);
    mx_set_matrices(idProgram_, vp);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glUniform1i(glGetUniformLocation(idProgram_, "u_objectId"), kNightSign);
    glDrawArrays(GL_TRIANGLES, 0, signVertices_);
    glUniform1i(glGetUniformLocation(idProgram_, "u_objectId"), kNightSphere);
    glDrawArrays(GL_TRIANGLES, signVertices_, sphereVertices_);
    const std::vector<float> geometry = read_target(W, H);

    NightImage img;
    img.width = st.width;
    img.height = st.height;
    img.scene = {scene.lights, scene.observationAtSign, scene.entranceAtSign};
    const size_t n = size_t(st.width) * size_t(st.height);
    img.alpha.assign(n, 0.0f);
    std::vector<int> passes = {-1};
    if (lobes())
        passes = chain_only(material_) ? std::vector<int>{0, 1, 2} : std::vector<int>{0, 1, 2, 3};
    std::vector<std::vector<double>> sums(4, std::vector<double>(3 * n, 0.0));
    // Sample s (row 0 at the bottom) of pixel i (row 0 at the top).
    auto pixel_of = [&](size_t s) {
        const size_t x = s % size_t(W), y = size_t(H - 1) - s / size_t(W);
        return (y / size_t(spp)) * size_t(st.width) + x / size_t(spp);
    };
    const double perSample = 1.0 / double(spp * spp);
    for (size_t s = 0; s < size_t(W) * size_t(H); ++s)
        if (geometry[4 * s + 3] > 0.5f) img.alpha[pixel_of(s)] += float(perSample);

    glUseProgram(program_);
    bind_attributes(program_, vao_, vbo_);
    mx_set_matrices(program_, vp);
    glUniform3f(glGetUniformLocation(program_, "u_viewPosition"), float(scene.eye.x),
                float(scene.eye.y), float(scene.eye.z));
    glUniform1i(glGetUniformLocation(program_, "u_numActiveLightSources"), 1);
    std::atomic<long> anomalies{0};
    std::vector<double> weight(size_t(W) * size_t(H));
    for (const NightLight& light : scene.lights) {
        // Per sample: I / d^2 where the light is in front of the surface and not shadowed.
        parallel_for(size_t(H), 0, [&](size_t row) {
            for (size_t s = row * size_t(W); s < (row + 1) * size_t(W); ++s) {
                weight[s] = 0;
                if (geometry[4 * s + 3] < 0.5f) continue;
                // A sphere sample lies on a flat triangle up to r (1 - cos(pi / 512)) = 9.4e-6
                // inside the sphere: its point on the sphere, as the reference hits it, so that
                // the shadow ray does not start inside.
                dvec3 p(geometry[4 * s], geometry[4 * s + 1], geometry[4 * s + 2]);
                const bool onSign = geometry[4 * s + 3] < 1.5f;
                const dvec3 nrm = onSign ? scene.sign.n : glm::normalize(p - scene.sphere.c);
                if (!onSign) p = scene.sphere.c + scene.sphere.r * nrm;
                const dvec3 toL = light.position - p;
                if (glm::dot(toL, nrm) <= 0 || glm::dot(scene.eye - p, nrm) <= 0) continue;
                if (scene.occluded(p, nrm, light.position)) continue;
                weight[s] = light.intensity / glm::dot(toL, toL);
            }
        });
        MxLight ml;
        ml.point = true;
        ml.position = {light.position.x, light.position.y, light.position.z};
        ml.intensity = 1;
        ml.decay_rate = 0;
        mx_set_light(program_, 0, ml);
        for (int pass : passes) {
            draw_pass(pass, W, H);
            const std::vector<float> px = read_target(W, H);
            std::vector<double>& sum = sums[size_t(pass < 0 ? 3 : pass)];
            for (size_t s = 0; s < size_t(W) * size_t(H); ++s) {
                if (weight[s] == 0) continue;
                const size_t i = pixel_of(s);
                for (size_t c = 0; c < 3; ++c) {
                    const float v = px[4 * s + c];
                    if (!std::isfinite(v) || v < 0) ++anomalies;
                    sum[3 * i + c] += double(v) * weight[s] * perSample;
                }
            }
        }
    }
    const GLenum err = glGetError();
    if (err != GL_NO_ERROR)
        throw GlError("OpenGL: error " + std::to_string(err) + " while rendering the scene");
    // A lobe's pass holds the lobe and the rest of the graph: the lobe is its pass less the
    // rest (clamped at 0 against float rounding).
    std::vector<float>* layers[4] = {&img.surface, &img.retro, &img.diffuse, &img.other};
    const bool rest = std::find(passes.begin(), passes.end(), 3) != passes.end();
    for (int pass : passes) {
        const size_t l = size_t(pass < 0 ? 3 : pass);
        layers[l]->resize(3 * n);
        for (size_t k = 0; k < 3 * n; ++k)
            (*layers[l])[k] =
                float(l < 3 && rest ? std::max(sums[l][k] - sums[3][k], 0.0) : sums[l][k]);
    }
    img.anomalies = anomalies;
    return img;
}

NightImage render_night_mx(const MxMaterial& material, const NightSettings& settings) {
    MxNightRenderer renderer(material);
    return renderer.render(settings);
}

} // namespace retroprism::gl
