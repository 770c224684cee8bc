// gl_runner.h: runs the generated GLSL on a real OpenGL implementation. An EGL surfaceless
// display (Mesa's llvmpipe where there is no GPU) gives an OpenGL 4.5 core context without a
// window; a compute shader calls the library's entry point once per direction pair.
#pragma once

#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "prismatic_retroreflector.h"

namespace retroprism::gl {

// No EGL display or OpenGL 4.5 context could be had, or a shader failed to build; the message
// says which step failed and what EGL or the GLSL compiler said.
class GlError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// An OpenGL 4.5 core context on an EGL surfaceless display, made current on creation. Several
// may live in one process; use() makes one current.
class EglContext {
  public:
    EglContext();
    ~EglContext();
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;
    void use() const;
    // GL_RENDERER and GL_VERSION.
    std::string renderer() const;

  private:
    void* display_ = nullptr;
    void* context_ = nullptr;
};

// Compiles and links a program from (type, source) stages; GlError with the compiler's log.
unsigned build_program(const std::vector<std::pair<unsigned, std::string>>& stages);

// Sets the uniform at `location` of the current program to the input `info` of p (float, vec3,
// int or bool as the parameter table types it); location -1 (not in the program) is ignored, as
// OpenGL ignores it.
void set_input_uniform(int location, const Params& p, const ParamInfo& info);

struct Result {
    std::array<float, 3> surface{};
    std::array<float, 3> retro{};
    std::array<float, 3> diffuse{};
    float pdf = 0;
};

class Runner {
  public:
    // Creates the context and compiles `library` (a generated variant) into a compute shader.
    explicit Runner(const std::string& library);
    ~Runner();
    Runner(const Runner&) = delete;
    Runner& operator=(const Runner&) = delete;

    // The node at each (wi, wo) pair with the given (unsanitised) inputs.
    std::vector<Result> evaluate(const Params& p, const std::vector<std::array<Vec3d, 2>>& pairs);
    // GL_RENDERER and GL_VERSION of the context.
    std::string renderer() const;

  private:
    EglContext context_;
    unsigned program_ = 0;
};

// The generated full-runtime variant, embedded in the binary at build time.
const std::string& embedded_library();

} // namespace retroprism::gl
