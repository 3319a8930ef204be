-- prints arg[0] and the arguments, one per line
print(arg[0])
for i = 1, #arg do print(i, arg[i]) end
