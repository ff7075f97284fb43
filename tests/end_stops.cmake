# placeholder (owned by a helper this session)
