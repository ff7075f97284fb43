# Hostile and careless mesh files (issue 15): label badinput. Included from tests/CMakeLists.txt.
