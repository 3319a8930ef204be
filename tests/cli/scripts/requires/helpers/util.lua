-- required by ../main.lua
return { answer = 42 }
