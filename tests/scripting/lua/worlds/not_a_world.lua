-- returns something that is not a world preset
return { name = "nope" }
