// Compiled only to produce the precompiled headers that geartopo's targets reuse (cmake/GeartopoLibrary.cmake).
