// OpenGL 3.3 core declarations: Apple's gl3.h, or Khronos' glcorearb.h with
// prototypes resolved by the system libGL (libglvnd exports the whole API).
#pragma once

#ifdef __APPLE__
#define GL_SILENCE_DEPRECATION
#include <OpenGL/gl3.h>
#else
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>
#endif
