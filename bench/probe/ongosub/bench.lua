local a, b, c = 0, 0, 0
local function f1() a = a + 1 end
local function f2() b = b + 2 end
local function f3() c = c + 3 end
local t = {f1, f2, f3}
for i = 1, 1000000 do t[i % 3 + 1]() end
print(a, b, c)
