# The modal scaling timing (validation/fe/modal_scaling.cpp), for validation/fe/CMakeLists.txt to
# include(). It is built but not registered as a ctest: one run takes tens of seconds on one core.
add_executable(jointhb_modal_scaling ${CMAKE_CURRENT_LIST_DIR}/modal_scaling.cpp)
target_link_libraries(jointhb_modal_scaling PRIVATE jointhb::jointhb jointhb_warnings)
