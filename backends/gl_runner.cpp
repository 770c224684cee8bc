#include "gl_runner.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cstdio>

namespace retroprism::gl {

namespace {

std::string egl_error_name(EGLint e) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "0x%04x", unsigned(e));
    return buf;
}

const char* glsl_type(ParamType type) {
    switch (type) {
    case ParamType::Float:
        return "float";
    case ParamType::Color:
    case ParamType::Vector:
        return "vec3";
    case ParamType::Enum:
        return "int";
    case ParamType::Bool:
        return "bool";
    }
    return "float";
}

// The compute shader around the library: pairs in, 10 floats per pair out.
std::string compute_source(const std::string& library) {
    std::string uniforms, args;
    for (const ParamInfo& info : param_table()) {
        uniforms += "uniform " + std::string(glsl_type(info.type)) + " u_" + info.name + ";\n";
        args += "u_" + std::string(info.name) + ", ";
    }
    return "#version 430\n"
           "layout(local_size_x = 64) in;\n" +
           library +
           "\nlayout(std430, binding = 0) readonly buffer RpPairs { vec4 rp_pairs[]; };\n"
           "layout(std430, binding = 1) writeonly buffer RpOut { float rp_out[]; };\n"
           "uniform int rp_count;\n" +
           uniforms +
           "void main() {\n"
           "    uint i = gl_GlobalInvocationID.x;\n"
           "    if (i >= uint(rp_count)) return;\n"
           "    vec3 surface;\n    vec3 retro;\n    vec3 diffuse;\n    float pdf;\n"
           "    rp_prismatic_retroreflector_eval(" +
           args +
           "rp_pairs[2u * i].xyz, rp_pairs[2u * i + 1u].xyz, surface, retro, diffuse, pdf);\n"
           "    uint o = 10u * i;\n"
           "    rp_out[o + 0u] = surface.x; rp_out[o + 1u] = surface.y; rp_out[o + 2u] = "
           "surface.z;\n"
           "    rp_out[o + 3u] = retro.x; rp_out[o + 4u] = retro.y; rp_out[o + 5u] = retro.z;\n"
           "    rp_out[o + 6u] = diffuse.x; rp_out[o + 7u] = diffuse.y; rp_out[o + 8u] = "
           "diffuse.z;\n"
           "    rp_out[o + 9u] = pdf;\n"
           "}\n";
}

} // namespace

void set_input_uniform(int location, const Params& p, const ParamInfo& info) {
    switch (info.type) {
    case ParamType::Float:
        glUniform1f(location, float(*input_field<double>(p, info.name)));
        break;
    case ParamType::Color:
    case ParamType::Vector: {
        const Vec3d& v = *input_field<Vec3d>(p, info.name);
        glUniform3f(location, float(v[0]), float(v[1]), float(v[2]));
        break;
    }
    case ParamType::Enum:
        glUniform1i(location, *input_field<int>(p, info.name));
        break;
    case ParamType::Bool:
        glUniform1i(location, *input_field<bool>(p, info.name) ? 1 : 0);
        break;
    }
}

EglContext::EglContext() {
    if (!epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless"))
        throw GlError("EGL: the client extension EGL_MESA_platform_surfaceless is missing "
                      "(install Mesa: libegl-mesa0 libgl1-mesa-dri)");
    EGLDisplay display =
        eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint major = 0, minor = 0;
    if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor))
        throw GlError("EGL: cannot initialise a surfaceless display (error " +
                      egl_error_name(eglGetError()) + ")");
    display_ = display;
    if (!eglBindAPI(EGL_OPENGL_API)) throw GlError("EGL: cannot bind the OpenGL API");
    const EGLint configAttribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                    EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint count = 0;
    if (!eglChooseConfig(display, configAttribs, &config, 1, &count) || count < 1) {
        if (!epoxy_has_egl_extension(display, "EGL_KHR_no_config_context"))
            throw GlError("EGL: no OpenGL-capable config on the surfaceless display");
        config = EGL_NO_CONFIG_KHR;
    }
    const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                     4,
                                     EGL_CONTEXT_MINOR_VERSION,
                                     5,
                                     EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                     EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                     EGL_NONE};
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttribs);
    if (context == EGL_NO_CONTEXT)
        throw GlError("EGL: cannot create an OpenGL 4.5 core context (error " +
                      egl_error_name(eglGetError()) + ")");
    context_ = context;
    use();
}

EglContext::~EglContext() {
    // The display is shared by every context of the process: only the context goes.
    if (context_) {
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display_, context_);
    }
}

void EglContext::use() const {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
        throw GlError("EGL: cannot make the context current without a surface (error " +
                      egl_error_name(eglGetError()) + ")");
}

std::string EglContext::renderer() const {
    use();
    const char* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const char* v = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    return std::string(r ? r : "?") + ", OpenGL " + (v ? v : "?");
}

unsigned build_program(const std::vector<std::pair<unsigned, std::string>>& stages) {
    GLuint program = glCreateProgram();
    for (const auto& [type, source] : stages) {
        const char* text = source.c_str();
        GLuint shader = glCreateShader(GLenum(type));
        glShaderSource(shader, 1, &text, nullptr);
        glCompileShader(shader);
        GLint ok = 0;
        glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
        if (!ok) {
            GLint len = 0;
            glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &len);
            std::string log(size_t(std::max(len, 1)), '\0');
            glGetShaderInfoLog(shader, len, nullptr, &log[0]);
            glDeleteShader(shader);
            glDeleteProgram(program);
            throw GlError("GLSL: a shader does not compile:\n" + log);
        }
        glAttachShader(program, shader);
        glDeleteShader(shader);
    }
    glLinkProgram(program);
    GLint ok = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint len = 0;
        glGetProgramiv(program, GL_INFO_LOG_LENGTH, &len);
        std::string log(size_t(std::max(len, 1)), '\0');
        glGetProgramInfoLog(program, len, nullptr, &log[0]);
        glDeleteProgram(program);
        throw GlError("GLSL: the program does not link:\n" + log);
    }
    return program;
}

Runner::Runner(const std::string& library)
    : program_(build_program({{GL_COMPUTE_SHADER, compute_source(library)}})) {}

Runner::~Runner() {
    context_.use();
    if (program_) glDeleteProgram(program_);
}

std::string Runner::renderer() const {
    return context_.renderer();
}

std::vector<Result> Runner::evaluate(const Params& p,
                                     const std::vector<std::array<Vec3d, 2>>& pairs) {
    std::vector<Result> results(pairs.size());
    if (pairs.empty()) return results;
    context_.use();
    glUseProgram(program_);
    auto loc = [&](const char* name) { return glGetUniformLocation(program_, name); };
    for (const ParamInfo& info : param_table())
        set_input_uniform(loc(("u_" + std::string(info.name)).c_str()), p, info);
    glUniform1i(loc("rp_count"), GLint(pairs.size()));
    std::vector<float> in(pairs.size() * 8);
    for (size_t i = 0; i < pairs.size(); ++i)
        for (int k = 0; k < 2; ++k)
            for (int c = 0; c < 3; ++c)
                in[8 * i + 4 * k + c] = float(pairs[i][k][c]);
    GLuint buffers[2];
    glGenBuffers(2, buffers);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffers[0]);
    glBufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(in.size() * sizeof(float)), in.data(),
                 GL_STATIC_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffers[0]);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffers[1]);
    glBufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(pairs.size() * 10 * sizeof(float)), nullptr,
                 GL_DYNAMIC_READ);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buffers[1]);
    glDispatchCompute(GLuint((pairs.size() + 63) / 64), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<float> out(pairs.size() * 10);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(out.size() * sizeof(float)),
                       out.data());
    glDeleteBuffers(2, buffers);
    GLenum err = glGetError();
    if (err != GL_NO_ERROR) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "OpenGL: error 0x%04x while evaluating", unsigned(err));
        throw GlError(buf);
    }
    for (size_t i = 0; i < pairs.size(); ++i) {
        const float* o = &out[10 * i];
        results[i].surface = {o[0], o[1], o[2]};
        results[i].retro = {o[3], o[4], o[5]};
        results[i].diffuse = {o[6], o[7], o[8]};
        results[i].pdf = o[9];
    }
    return results;
}

} // namespace retroprism::gl
