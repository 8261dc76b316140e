#pragma once
// Private to the engine: one float vertex attribute of an interleaved buffer bound at
// binding 0 of a vertex array (DSA).
#include "LoaderGL.h"

#include <cstddef>

namespace atmoglobe::engine {

inline void floatAttributeGL(GLuint vao, GLuint index, GLint components, std::size_t offsetBytes) {
  glEnableVertexArrayAttrib(vao, index);
  glVertexArrayAttribFormat(vao, index, components, GL_FLOAT, GL_FALSE, static_cast<GLuint>(offsetBytes));
  glVertexArrayAttribBinding(vao, index, 0);
}

}  // namespace atmoglobe::engine
