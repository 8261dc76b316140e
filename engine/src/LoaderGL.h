#pragma once
// The GL loader (libepoxy) for the engine's sources. The public headers do not include it: they
// name GL objects and enums with plain types (GLuint, GLenum: unsigned int; GLint, GLsizei: int),
// so a program using the engine needs no GL loader header. Checked here, for every source.
#include <epoxy/gl.h>

#include <type_traits>

static_assert(std::is_same_v<GLuint, unsigned int>, "public headers use unsigned int for GLuint");
static_assert(std::is_same_v<GLenum, unsigned int>, "public headers use unsigned int for GLenum");
static_assert(std::is_same_v<GLint, int>, "public headers use int for GLint");
static_assert(std::is_same_v<GLsizei, int>, "public headers use int for GLsizei");
