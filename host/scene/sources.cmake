# host/scene's sources, relative to this folder: the library (CMakeLists.txt here) and the fuzz
# targets (fuzz/CMakeLists.txt, which compile them with sanitizers) read the one list.
set(OAS_SCENE_SOURCE_FILES
    scene.cpp scene_fields.cpp scene_json.cpp scene_camera.cpp scene_materials.cpp scene_shapes.cpp
    scene_lights.cpp scene_settings.cpp obj.cpp bvh.cpp)
