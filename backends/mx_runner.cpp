#include "mx_runner.h"

#include <epoxy/gl.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace retroprism::gl {

namespace {

namespace fs = std::filesystem;

const char* const kDocument =
    "<?xml version=\"1.0\"?>\n"
    "<materialx version=\"1.39\">\n"
    "  <rp_prismatic_retroreflector_bsdf name=\"rp_query_bsdf\" type=\"BSDF\"/>\n"
    "  <surface name=\"rp_query_surface\" type=\"surfaceshader\">\n"
    "    <input name=\"bsdf\" type=\"BSDF\" nodename=\"rp_query_bsdf\"/>\n"
    "  </surface>\n"
    "  <surfacematerial name=\"rp_query\" type=\"material\">\n"
    "    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"rp_query_surface\"/>\n"
    "  </surfacematerial>\n"
    "</materialx>\n";

// The fragment stage that writes the interpolated world position instead of the shading.
const char* const kPositionFragment =
    "#version 400\n"
    "in VertexData { vec3 normalWorld; vec3 tangentWorld; vec3 positionWorld; } vd;\n"
    "out vec4 out1;\n"
    "void main() { out1 = vec4(vd.positionWorld, 1.0); }\n";

std::string read_text(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    if (!in) throw GlError("MaterialX: " + p.string() + " was not generated");
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

Mat4 identity() {
    return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
}

Mat4 multiply(const Mat4& a, const Mat4& b) {
    Mat4 r{};
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row) {
            float s = 0;
            for (int k = 0; k < 4; ++k)
                s += a[size_t(k * 4 + row)] * b[size_t(c * 4 + k)];
            r[size_t(c * 4 + row)] = s;
        }
    return r;
}

glm::dvec3 vec(const Vec3d& v) {
    return glm::dvec3(v[0], v[1], v[2]);
}

} // namespace

void generate_mx_shaders(const std::string& dataDir, const std::vector<std::string>& documents,
                         const std::string& outDir, const MxGenerateOptions& options) {
    const fs::path tool = fs::path(dataDir) / "materialx" / "tools" / "mx.cjs";
    if (!fs::exists(fs::path(dataDir) / "materialx" / "tools" / "node_modules" / "@needle-tools"))
        throw GlError("MaterialX: materialx/tools is not installed (run scripts/setup-debian.sh, "
                      "which runs npm ci there)");
    std::string cmd = "node '" + tool.string() + "' generate --targets '" + options.targets + "'";
    if (options.portable) cmd += " --portable";
    for (const std::string& d : documents)
        cmd += " '" + d + "'";
    cmd += " '" + outDir + "' 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) throw GlError("MaterialX: cannot run node");
    std::string out;
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0)
        out.append(buf, n);
    int st = pclose(p);
    if (!WIFEXITED(st) || WEXITSTATUS(st) != 0)
        throw GlError("MaterialX: shader generation failed (" + cmd + "):\n" + out);
}

MxShaders read_mx_shaders(const std::string& dir, const std::string& material) {
    return {read_text(fs::path(dir) / (material + ".glsl.vert")),
            read_text(fs::path(dir) / (material + ".glsl.frag"))};
}

namespace {

// The GLSL shaders of `material` of `document` (empty: the one-node query document), of the
// portable nodegraph when `portable`.
MxShaders generated_shaders(const std::string& dataDir, const std::string& document,
                            const std::string& material, bool portable) {
    const fs::path dir =
        fs::temp_directory_path() / ("retroprism_mx_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    fs::path doc = document;
    if (document.empty()) {
        doc = dir / "rp_query.mtlx";
        std::ofstream(doc) << kDocument;
    }
    generate_mx_shaders(dataDir, {doc.string()}, dir.string(), {"glsl", portable});
    MxShaders shaders = read_mx_shaders(dir.string(), material);
    fs::remove_all(dir);
    return shaders;
}

} // namespace

const char* mx_query_document() {
    return kDocument;
}

MaterialXRunner::MaterialXRunner(const std::string& sourceDir, const std::string& document,
                                 const std::string& material, const std::string& node,
                                 bool portable)
    : MaterialXRunner(generated_shaders(sourceDir, document, material, portable), node) {}

MaterialXRunner::MaterialXRunner(const MxShaders& shaders, const std::string& node)
    : node_(node), vertex_(shaders.vertex), fragment_(shaders.fragment) {
    program_ = build_program({{GL_VERTEX_SHADER, vertex_}, {GL_FRAGMENT_SHADER, fragment_}});
    posProgram_ =
        build_program({{GL_VERTEX_SHADER, vertex_}, {GL_FRAGMENT_SHADER, kPositionFragment}});
    glGenVertexArrays(1, &vao_);
    glGenBuffers(1, &vbo_);
    glGenFramebuffers(1, &fbo_);
    glGenTextures(1, &colorTex_);
    glGenTextures(1, &envTex_);
    const float black[4] = {0, 0, 0, 0};
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, envTex_);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, 1, 1, 0, GL_RGBA, GL_FLOAT, black);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glActiveTexture(GL_TEXTURE0);
}

MaterialXRunner::~MaterialXRunner() {
    context_.use();
    glDeleteTextures(1, &envTex_);
    glDeleteTextures(1, &colorTex_);
    glDeleteFramebuffers(1, &fbo_);
    glDeleteBuffers(1, &vbo_);
    glDeleteVertexArrays(1, &vao_);
    glDeleteProgram(posProgram_);
    glDeleteProgram(program_);
}

void MaterialXRunner::set_material(const Params& p) {
    auto loc = [&](const std::string& input) {
        // The node's uniforms in MaterialX's shader are "<node>_<input>".
        return glGetUniformLocation(program_, (node_ + "_" + input).c_str());
    };
    for (const ParamInfo& info : param_table())
        if (info.type != ParamType::Vector) // from the geometry: see the quad's attributes
            set_input_uniform(loc(info.name), p, info);
    // No environment light: only the lights given contribute.
    glUniform1f(glGetUniformLocation(program_, "u_envLightIntensity"), 0.0f);
    bind_environment(program_, envTex_);
}

void MaterialXRunner::set_inputs(const Params& p) {
    context_.use();
    glUseProgram(program_);
    set_material(p);
}

namespace {

// A quad over [-1, 1]^2 at z = 0 with constant normal and tangent attributes.
void upload_quad(unsigned program, unsigned vao, unsigned vbo, const Vec3d& n, const Vec3d& t) {
    const float N[3] = {float(n[0]), float(n[1]), float(n[2])};
    const float T[3] = {float(t[0]), float(t[1]), float(t[2])};
    const float corners[6][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, -1}, {1, 1}, {-1, 1}};
    std::vector<float> data;
    for (const auto& c : corners) {
        data.insert(data.end(), {c[0], c[1], 0.0f});
        data.insert(data.end(), N, N + 3);
        data.insert(data.end(), T, T + 3);
    }
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(data.size() * sizeof(float)), data.data(),
                 GL_STATIC_DRAW);
    const char* names[3] = {"i_position", "i_normal", "i_tangent"};
    for (int a = 0; a < 3; ++a) {
        GLint location = glGetAttribLocation(program, names[a]);
        if (location < 0) continue;
        glEnableVertexAttribArray(GLuint(location));
        glVertexAttribPointer(GLuint(location), 3, GL_FLOAT, GL_FALSE, 9 * sizeof(float),
                              reinterpret_cast<const void*>(size_t(a) * 3 * sizeof(float)));
    }
}

void target(unsigned fbo, unsigned tex, int w, int h) {
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, w, h, 0, GL_RGBA, GL_FLOAT, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw GlError("OpenGL: the RGBA32F render target is incomplete");
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
}

} // namespace

void mx_set_light(unsigned program, int i, const MxLight& l) {
    auto loc = [&](const char* field) {
        return glGetUniformLocation(program,
                                    ("u_lightData[" + std::to_string(i) + "]." + field).c_str());
    };
    // Light types as mx.cjs binds them: 1 directional, 2 point.
    glUniform1i(loc("type"), l.point ? 2 : 1);
    glUniform3f(loc("direction"), float(l.direction[0]), float(l.direction[1]),
                float(l.direction[2]));
    glUniform3f(loc("position"), float(l.position[0]), float(l.position[1]), float(l.position[2]));
    glUniform3f(loc("color"), float(l.color[0]), float(l.color[1]), float(l.color[2]));
    glUniform1f(loc("intensity"), float(l.intensity));
    glUniform1f(loc("decay_rate"), float(l.decay_rate));
}

void mx_set_matrices(unsigned program, const Mat4& viewProjection) {
    const Mat4 id = identity();
    glUniformMatrix4fv(glGetUniformLocation(program, "u_worldMatrix"), 1, GL_FALSE, id.data());
    glUniformMatrix4fv(glGetUniformLocation(program, "u_worldInverseTransposeMatrix"), 1, GL_FALSE,
                       id.data());
    glUniformMatrix4fv(glGetUniformLocation(program, "u_viewProjectionMatrix"), 1, GL_FALSE,
                       viewProjection.data());
}

// The environment samplers read the black texture on unit 1.
void MaterialXRunner::bind_environment(unsigned program, unsigned envTex) {
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, envTex);
    glActiveTexture(GL_TEXTURE0);
    for (const char* name : {"u_envRadiance", "u_envIrradiance"}) {
        const GLint loc = glGetUniformLocation(program, name);
        if (loc >= 0) glUniform1i(loc, 1);
    }
}

std::vector<Result> MaterialXRunner::evaluate(const Params& p,
                                              const std::vector<std::array<Vec3d, 2>>& pairs) {
    std::vector<Result> results(pairs.size());
    if (pairs.empty()) return results;
    context_.use();
    const Params s = sanitize(p);
    const int w = int(std::min<size_t>(pairs.size(), 256));
    const int h = int((pairs.size() + size_t(w) - 1) / size_t(w));
    glUseProgram(program_);
    // The quad spans the whole viewport, so a 1 x 1 viewport's one fragment sits at its
    // centre: the world origin, where V = normalize(u_viewPosition).
    upload_quad(program_, vao_, vbo_, s.normal, s.tangent);
    mx_set_matrices(program_, identity());
    glUniform1i(glGetUniformLocation(program_, "u_numActiveLightSources"), 1);
    std::vector<float> pixels(size_t(w) * size_t(h) * 4);
    for (int lobe = 0; lobe < 3; ++lobe) {
        // Each lobe alone: the other two lobes' weight or colour is 0.
        Params alone = s;
        if (lobe != 0) alone.specular = 0;
        if (lobe != 1) alone.retro_color = {0, 0, 0};
        if (lobe != 2) alone.diffuse_color = {0, 0, 0};
        set_material(alone);
        target(fbo_, colorTex_, w, h);
        for (size_t k = 0; k < pairs.size(); ++k) {
            const Vec3d& wi = pairs[k][0];
            const Vec3d& wo = pairs[k][1];
            MxLight light;
            light.direction = {-wi[0], -wi[1], -wi[2]};
            mx_set_light(program_, 0, light);
            glUniform3f(glGetUniformLocation(program_, "u_viewPosition"), float(wo[0]),
                        float(wo[1]), float(wo[2]));
            glViewport(GLint(k % size_t(w)), GLint(k / size_t(w)), 1, 1);
            glDrawArrays(GL_TRIANGLES, 0, 6);
        }
        glReadPixels(0, 0, w, h, GL_RGBA, GL_FLOAT, pixels.data());
        for (size_t k = 0; k < pairs.size(); ++k) {
            // response = f (N.L) with N facing the viewer (MaterialX's convention) and the
            // frame normal the node builds from it.
            glm::dvec3 wiV = glm::normalize(vec(pairs[k][0])),
                       woV = glm::normalize(vec(pairs[k][1]));
            glm::dvec3 n = vec(s.normal);
            if (glm::dot(n, woV) < 0) n = -n;
            const double cosI = std::max(glm::dot(n, wiV), 0.0);
            std::array<float, 3>& out = lobe == 0   ? results[k].surface
                                        : lobe == 1 ? results[k].retro
                                                    : results[k].diffuse;
            for (int c = 0; c < 3; ++c)
                out[size_t(c)] = cosI > 0 ? float(double(pixels[4 * k + size_t(c)]) / cosI) : 0.0f;
        }
    }
    for (Result& r : results)
        r.pdf = std::nanf("");
    GLenum err = glGetError();
    if (err != GL_NO_ERROR)
        throw GlError("OpenGL: error " + std::to_string(err) + " while rendering");
    return results;
}

MxImage MaterialXRunner::render(int w, int h, const Vec3d& eye, double fovDeg,
                                const std::vector<MxLight>& lights) {
    context_.use();
    MxImage img;
    img.width = w;
    img.height = h;
    // Camera: look at the origin, up +y (or +z when looking along y).
    glm::dvec3 e = vec(eye), f = glm::normalize(-e);
    glm::dvec3 up = std::abs(f.y) > 0.99 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
    glm::dvec3 r = glm::normalize(glm::cross(f, up)), u = glm::cross(r, f);
    Mat4 view = {float(r.x),
                 float(u.x),
                 float(-f.x),
                 0,
                 float(r.y),
                 float(u.y),
                 float(-f.y),
                 0,
                 float(r.z),
                 float(u.z),
                 float(-f.z),
                 0,
                 float(-glm::dot(r, e)),
                 float(-glm::dot(u, e)),
                 float(glm::dot(f, e)),
                 1};
    const double nearZ = 0.01, farZ = 100.0, t = 1.0 / std::tan(fovDeg * M_PI / 360.0);
    Mat4 proj = {float(t * h / w),
                 0,
                 0,
                 0,
                 0,
                 float(t),
                 0,
                 0,
                 0,
                 0,
                 float((farZ + nearZ) / (nearZ - farZ)),
                 -1,
                 0,
                 0,
                 float(2 * farZ * nearZ / (nearZ - farZ)),
                 0};
    const Mat4 vp = multiply(proj, view);
    for (int pass = 0; pass < 2; ++pass) {
        const unsigned prog = pass == 0 ? program_ : posProgram_;
        glUseProgram(prog);
        upload_quad(prog, vao_, vbo_, {0, 0, 1}, {1, 0, 0});
        mx_set_matrices(prog, vp);
        if (pass == 0) {
            glUniform1f(glGetUniformLocation(prog, "u_envLightIntensity"), 0.0f);
            bind_environment(prog, envTex_);
            glUniform3f(glGetUniformLocation(prog, "u_viewPosition"), float(eye[0]), float(eye[1]),
                        float(eye[2]));
            glUniform1i(glGetUniformLocation(prog, "u_numActiveLightSources"), int(lights.size()));
            for (size_t i = 0; i < lights.size(); ++i)
                mx_set_light(prog, int(i), lights[i]);
        }
        target(fbo_, colorTex_, w, h);
        glViewport(0, 0, w, h);
        glDrawArrays(GL_TRIANGLES, 0, 6);
        std::vector<float>& dst = pass == 0 ? img.rgba : img.positionWorld;
        std::vector<float> px(size_t(w) * size_t(h) * 4);
        glReadPixels(0, 0, w, h, GL_RGBA, GL_FLOAT, px.data());
        if (pass == 0) {
            dst = px;
        } else {
            dst.resize(size_t(w) * size_t(h) * 3);
            for (size_t i = 0; i < size_t(w) * size_t(h); ++i)
                for (int c = 0; c < 3; ++c)
                    dst[3 * i + size_t(c)] = px[4 * i + size_t(c)];
        }
    }
    GLenum err = glGetError();
    if (err != GL_NO_ERROR)
        throw GlError("OpenGL: error " + std::to_string(err) + " while rendering");
    return img;
}

} // namespace retroprism::gl
