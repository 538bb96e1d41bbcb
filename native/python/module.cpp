// The whitted_native Python module: the native Whitted ray tracer.
#include "bindings.h"

PYBIND11_MODULE(whitted_native, m) {
  m.doc() = "Whitted: a native Whitted (1980) ray tracer on Embree.";
  whitted::python::bind_panorama(m);
  whitted::python::bind_camera(m);
  whitted::python::bind_light(m);
  whitted::python::bind_program(m);
  whitted::python::bind_material(m);
  whitted::python::bind_texture(m);
  whitted::python::bind_mesh(m);
  whitted::python::bind_scene(m);
  whitted::python::bind_settings(m);
  whitted::python::bind_render(m);
  whitted::python::bind_denoise(m);
  whitted::python::bind_volume_object(m);
}
