local a, b = 0, 0
local function step() local c = (a + b) % 1000003; a = b; b = c + 1 end
for i = 1, 1000000 do step() end
print(a, b)
